//! The HEADER of format version 4 and the scene of a checkpoint as named [records](super::record).
//!
//! Keys (every array resolved, `N` beads, `N − 1` contacts; `?` = only when present):
//!
//! | key | value |
//! |---|---|
//! | `crate_version`, `created_by` | text (version of the writing beadchain; its command line, or `python: beadchain.run(NAME)`) |
//! | `build_commit`? | text: git commit of the writing build (40 hex digits, `-dirty` suffix possible, or `unknown`); left out with `BEADCHAIN_NO_BUILD_COMMIT=1` and in files of builds before it |
//! | `created_at`? | text: UTC start of the run, `YYYY-MM-DDTHH:MM:SSZ`; only `run --timing` writes it |
//! | `engine`, `method` | text (`hybrid`/`dense`; `auto`, `radau5`, `dop853`, `verlet`) |
//! | `rtol`, `atol` | real |
//! | `seed`, `n_beads` | integer |
//! | `output.beads`? | integers (stored beads); `output.fields`: text (`u,v`, `u`, `v`); `output.frames_max`?: integer |
//! | `scene.name`, `scene.description` | text; `scene.seed`: integer |
//! | `scene.units.mass`, `.time`, `.mu`, `.n0`? | real (physical scenes: m0 in kg, β in s, μ, n0; paper eq. 10) |
//! | `chain.mass` | N reals; `chain.exponent`, `chain.prefactor`: N − 1 reals |
//! | `chain.precompression`? | N − 1 reals; `chain.field`?: N reals |
//! | `chain.left_wall.exponent`?, `.prefactor`, `.precompression`, `.restitution`? | real (same for `right_wall`) |
//! | `chain.hard.restitution`? | N − 1 optional reals; `chain.hard.collapse_interval`: real |
//! | `chain.damping.law`? | text; `chain.damping.contact`: N − 1 reals; `.left_wall`, `.right_wall`: real |
//! | `initial.u`, `initial.v` | N reals |
//! | `run.until` | real; `run.every`?, `run.rtol`?, `run.atol`?: real; `run.method`?, `run.engine`?: text |
//!
//! `build_commit` and `created_at` came after the first format-4 files, as optional keys: files
//! without them still read (golden file `data/golden/v4_no_provenance.snap`), so the format
//! version stayed 4. A reader built before them refuses a file that has them (unknown key, as
//! for any key added since: see [`super::record`]), with an error that names the key and says
//! it was written by a newer beadchain.

use super::record::{pick, RecordError, RecordReader, RecordWriter, Value};
use super::select::{Fields, Selection};
use super::Header;
use crate::integrate::Method;
use crate::model::{Chain, Damping, DampingLaw, HardContacts, Wall};
use crate::names::Named;
use crate::scene::{Engine, RunSettings, Scene, UnitScales};

const METHODS: [Method; 4] = [Method::Auto, Method::Radau5, Method::Dop853, Method::Verlet];
const ENGINES: [Engine; 2] = [Engine::Hybrid, Engine::Dense];
const FIELDS: [Fields; 3] = [Fields::Both, Fields::U, Fields::V];
const LAWS: [DampingLaw; 2] = [DampingLaw::Viscoelastic, DampingLaw::LinearDashpot];

/// The HEADER as a record (`format_version` is the file's preamble, not an entry).
pub fn header_record(h: &Header) -> Vec<(String, Value)> {
    let Header {
        format_version: _,
        crate_version,
        scene,
        engine,
        method,
        rtol,
        atol,
        seed,
        n_beads,
        created_by,
        output,
        build_commit,
        created_at,
    } = h;
    let mut w = RecordWriter::default();
    w.text("crate_version", crate_version);
    if let Some(c) = build_commit {
        w.text("build_commit", c);
    }
    if let Some(d) = created_at {
        w.text("created_at", d);
    }
    w.text("created_by", created_by);
    w.text("engine", engine.name());
    w.text("method", method.name());
    w.real("rtol", *rtol);
    w.real("atol", *atol);
    w.int("seed", *seed);
    w.int("n_beads", *n_beads);
    let Selection {
        beads,
        fields,
        frames_max,
    } = output;
    if let Some(b) = beads {
        w.put("output.beads", Value::Ints(b.clone()));
    }
    w.text("output.fields", fields.name());
    if let Some(k) = frames_max {
        w.int("output.frames_max", *k);
    }
    put_scene(&mut w, scene);
    w.finish()
}

/// The HEADER of a version-4 file from its record.
pub fn header_from_record(entries: Vec<(String, Value)>) -> Result<Header, RecordError> {
    let mut r = RecordReader::new(entries)?;
    let crate_version = r.text("crate_version")?;
    let build_commit = r.opt_text("build_commit")?;
    let created_at = r.opt_text("created_at")?;
    let created_by = r.text("created_by")?;
    let engine = pick("engine", &r.text("engine")?, &ENGINES, Engine::name)?;
    let method = pick("method", &r.text("method")?, &METHODS, Method::name)?;
    let (rtol, atol) = (r.real("rtol")?, r.real("atol")?);
    let (seed, n_beads) = (r.int("seed")?, r.int("n_beads")?);
    let output = Selection {
        beads: r.opt_ints("output.beads")?,
        fields: pick(
            "output.fields",
            &r.text("output.fields")?,
            &FIELDS,
            Fields::name,
        )?,
        frames_max: r.opt_int("output.frames_max")?,
    };
    let scene = get_scene(&mut r)?;
    r.finish()?;
    if scene.chain.len() as u64 != n_beads {
        return Err(RecordError::BeadCount {
            n_beads,
            mass: scene.chain.len(),
        });
    }
    Ok(Header {
        format_version: 4,
        crate_version,
        scene,
        engine,
        method,
        rtol,
        atol,
        seed,
        n_beads,
        created_by,
        output,
        build_commit,
        created_at,
    })
}

/// Appends the scene's entries.
pub(crate) fn put_scene(w: &mut RecordWriter, s: &Scene) {
    let Scene {
        name,
        description,
        chain,
        u0,
        v0,
        run,
        seed,
        units,
    } = s;
    w.text("scene.name", name);
    w.text("scene.description", description);
    w.int("scene.seed", *seed);
    if let Some(UnitScales { mass, time, mu, n0 }) = units {
        w.real("scene.units.mass", *mass);
        w.real("scene.units.time", *time);
        w.real("scene.units.mu", *mu);
        w.real("scene.units.n0", *n0);
    }
    put_chain(w, chain);
    w.reals("initial.u", u0);
    w.reals("initial.v", v0);
    // `output` is the `[output]` table the run resolved into the header's `output.*` keys.
    let RunSettings {
        until,
        every,
        rtol,
        atol,
        method,
        engine,
        output: _,
    } = run;
    w.real("run.until", *until);
    w.opt_real("run.every", *every);
    w.opt_real("run.rtol", *rtol);
    w.opt_real("run.atol", *atol);
    if let Some(m) = method {
        w.text("run.method", m.name());
    }
    if let Some(e) = engine {
        w.text("run.engine", e.name());
    }
}

fn put_chain(w: &mut RecordWriter, c: &Chain) {
    let Chain {
        mass,
        exponent,
        prefactor,
        precompression,
        field,
        left_wall,
        right_wall,
        hard,
        damping,
    } = c;
    w.reals("chain.mass", mass);
    w.reals("chain.exponent", exponent);
    w.reals("chain.prefactor", prefactor);
    w.opt_reals("chain.precompression", precompression.as_deref());
    w.opt_reals("chain.field", field.as_deref());
    for (side, wall) in [("left_wall", left_wall), ("right_wall", right_wall)] {
        if let Some(Wall {
            exponent,
            prefactor,
            precompression,
            restitution,
        }) = wall
        {
            w.real(&format!("chain.{side}.exponent"), *exponent);
            w.real(&format!("chain.{side}.prefactor"), *prefactor);
            w.real(&format!("chain.{side}.precompression"), *precompression);
            w.opt_real(&format!("chain.{side}.restitution"), *restitution);
        }
    }
    if let Some(HardContacts {
        restitution,
        collapse_interval,
    }) = hard
    {
        w.put(
            "chain.hard.restitution",
            Value::OptReals(restitution.clone()),
        );
        w.real("chain.hard.collapse_interval", *collapse_interval);
    }
    if let Some(Damping {
        law,
        contact,
        left_wall,
        right_wall,
    }) = damping
    {
        w.text("chain.damping.law", law.name());
        w.reals("chain.damping.contact", contact);
        w.real("chain.damping.left_wall", *left_wall);
        w.real("chain.damping.right_wall", *right_wall);
    }
}

/// Takes the scene's entries.
pub(crate) fn get_scene(r: &mut RecordReader) -> Result<Scene, RecordError> {
    let name = r.text("scene.name")?;
    let description = r.text("scene.description")?;
    let seed = r.int("scene.seed")?;
    let units = match r.opt_real("scene.units.mass")? {
        None => None,
        Some(mass) => Some(UnitScales {
            mass,
            time: r.real("scene.units.time")?,
            mu: r.real("scene.units.mu")?,
            n0: r.real("scene.units.n0")?,
        }),
    };
    let chain = get_chain(r)?;
    let n = chain.len();
    let u0 = r.reals("initial.u", n)?;
    let v0 = r.reals("initial.v", n)?;
    let method = match r.opt_text("run.method")? {
        Some(m) => Some(pick("run.method", &m, &METHODS, Method::name)?),
        None => None,
    };
    let engine = match r.opt_text("run.engine")? {
        Some(e) => Some(pick("run.engine", &e, &ENGINES, Engine::name)?),
        None => None,
    };
    let run = RunSettings {
        until: r.real("run.until")?,
        every: r.opt_real("run.every")?,
        rtol: r.opt_real("run.rtol")?,
        atol: r.opt_real("run.atol")?,
        method,
        engine,
        output: None,
    };
    Ok(Scene {
        name,
        description,
        chain,
        u0,
        v0,
        run,
        seed,
        units,
    })
}

fn get_chain(r: &mut RecordReader) -> Result<Chain, RecordError> {
    let mass = r.reals_any("chain.mass")?;
    let n = mass.len();
    if n == 0 {
        return Err(RecordError::NoBeads("chain.mass".into()));
    }
    let nc = n - 1;
    let mut walls = [None, None];
    for (k, side) in ["left_wall", "right_wall"].into_iter().enumerate() {
        if let Some(exponent) = r.opt_real(&format!("chain.{side}.exponent"))? {
            walls[k] = Some(Wall {
                exponent,
                prefactor: r.real(&format!("chain.{side}.prefactor"))?,
                precompression: r.real(&format!("chain.{side}.precompression"))?,
                restitution: r.opt_real(&format!("chain.{side}.restitution"))?,
            });
        }
    }
    let [left_wall, right_wall] = walls;
    let hard = match r.opt_opt_reals("chain.hard.restitution", nc)? {
        None => None,
        Some(restitution) => Some(HardContacts {
            restitution,
            collapse_interval: r.real("chain.hard.collapse_interval")?,
        }),
    };
    let damping = match r.opt_text("chain.damping.law")? {
        None => None,
        Some(law) => Some(Damping {
            law: pick("chain.damping.law", &law, &LAWS, DampingLaw::name)?,
            contact: r.reals("chain.damping.contact", nc)?,
            left_wall: r.real("chain.damping.left_wall")?,
            right_wall: r.real("chain.damping.right_wall")?,
        }),
    };
    Ok(Chain {
        exponent: r.reals("chain.exponent", nc)?,
        prefactor: r.reals("chain.prefactor", nc)?,
        precompression: r.opt_reals("chain.precompression", nc)?,
        field: r.opt_reals("chain.field", n)?,
        mass,
        left_wall,
        right_wall,
        hard,
        damping,
    })
}

/// The named record of `scene` as a checkpoint stores it ([`scene_as_record`]).
pub(crate) fn scene_record(scene: &Scene) -> Vec<(String, Value)> {
    let mut w = RecordWriter::default();
    put_scene(&mut w, scene);
    w.finish()
}

/// `#[serde(with = "scene_as_record")]`: a [`Scene`] stored as its named record (checkpoints).
pub mod scene_as_record {
    use super::*;
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    /// Serializes the record of `scene`.
    pub fn serialize<S: Serializer>(scene: &Scene, s: S) -> Result<S::Ok, S::Error> {
        scene_record(scene).serialize(s)
    }

    /// Reads a scene record.
    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Scene, D::Error> {
        let entries = Vec::<(String, Value)>::deserialize(d)?;
        let mut r = RecordReader::new(entries).map_err(serde::de::Error::custom)?;
        let scene = get_scene(&mut r).map_err(serde::de::Error::custom)?;
        r.finish().map_err(serde::de::Error::custom)?;
        Ok(scene)
    }
}
