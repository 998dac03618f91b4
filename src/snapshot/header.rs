//! The HEADER section across format versions, and reading it alone from a file.
//!
//! Version 4 stores a named record ([`super::header4`]); versions 1–3 stored the internal structs
//! through bincode, decoded here through frozen copies of their layouts.
//!
//! Version 3 appends [`Header::output`] (the [output selection](super::select)) to the header
//! of versions 1 and 2; bincode stores fields in order without names, so the older layout is
//! decoded through [`HeaderV2`] and gets the full selection (every bead, both fields), which is
//! what those files hold. Version 3 also added `Chain::damping`: the older scene layout is frozen
//! here too ([`SceneV2`]).

use super::select::Selection;
use super::{
    decode_exact, section_hasher, Header, SnapshotError, MAGIC, PREAMBLE_LEN, SECTION_HEADER_LEN,
    TAG_HEADER,
};
use crate::integrate::Method;
use crate::model::{Chain, HardContacts, Wall};
use crate::scene::{Engine, RunSettings, Scene, UnitScales};
use serde::Deserialize;
use std::io::Read;
use std::path::Path;

/// `Chain` as versions 1 and 2 stored it (no `damping`).
#[derive(Deserialize)]
struct ChainV2 {
    mass: Vec<f64>,
    exponent: Vec<f64>,
    prefactor: Vec<f64>,
    precompression: Option<Vec<f64>>,
    field: Option<Vec<f64>>,
    left_wall: Option<Wall>,
    right_wall: Option<Wall>,
    hard: Option<HardContacts>,
}

/// `Scene` as versions 1 and 2 stored it.
#[derive(Deserialize)]
struct SceneV2 {
    name: String,
    description: String,
    chain: ChainV2,
    u0: Vec<f64>,
    v0: Vec<f64>,
    run: RunSettings,
    seed: u64,
}

impl SceneV2 {
    /// Today's scene: a version-1/2 chain is conservative (`damping = None`).
    fn upgrade(self) -> Scene {
        let c = self.chain;
        let units = units_from_description(&self.description);
        Scene {
            name: self.name,
            description: self.description,
            chain: Chain {
                mass: c.mass,
                exponent: c.exponent,
                prefactor: c.prefactor,
                precompression: c.precompression,
                field: c.field,
                left_wall: c.left_wall,
                right_wall: c.right_wall,
                hard: c.hard,
                damping: None,
            },
            u0: self.u0,
            v0: self.v0,
            run: self.run,
            seed: self.seed,
            units,
        }
    }
}

/// The unit scales a version 1–3 header recorded in the scene description
/// (`[physical units: time unit β s, mass unit m0 kg, mu μ, n0 n0; …]`, β and m0 to seven
/// significant digits); format 4 stores [`Scene::units`] in full.
pub(crate) fn units_from_description(d: &str) -> Option<UnitScales> {
    let tag = &d[d.find("[physical units: ")?..];
    let num = |key: &str| -> Option<f64> {
        let rest = &tag[tag.find(key)? + key.len()..];
        let end = rest.find([' ', ',', ';', ']']).unwrap_or(rest.len());
        rest[..end].parse().ok()
    };
    Some(UnitScales {
        time: num("time unit ")?,
        mass: num("mass unit ")?,
        mu: num("mu ")?,
        n0: num("n0 ")?,
    })
}

/// The header of format versions 1 and 2 ([`Header`] without `output`, its scene without
/// damping).
#[derive(Deserialize)]
struct HeaderV2 {
    format_version: u32,
    crate_version: String,
    scene: SceneV2,
    engine: Engine,
    method: Method,
    rtol: f64,
    atol: f64,
    seed: u64,
    n_beads: u64,
    created_by: String,
}

/// `Scene` as version 3 stored it (no `units`: they were only in the description).
#[derive(Deserialize)]
struct SceneV3 {
    name: String,
    description: String,
    chain: Chain,
    u0: Vec<f64>,
    v0: Vec<f64>,
    run: RunSettings,
    seed: u64,
}

/// The header of format version 3 (the internal structs through bincode).
#[derive(Deserialize)]
struct HeaderV3 {
    format_version: u32,
    crate_version: String,
    scene: SceneV3,
    engine: Engine,
    method: Method,
    rtol: f64,
    atol: f64,
    seed: u64,
    n_beads: u64,
    created_by: String,
    output: Selection,
}

/// Why a HEADER payload is corrupt (the detail of [`SnapshotError::Corrupt`]).
#[derive(Debug, thiserror::Error)]
pub(crate) enum HeaderError {
    /// The payload does not decode.
    #[error(transparent)]
    Decode(#[from] super::DecodeError),
    /// A version-4 record is invalid.
    #[error(transparent)]
    Record(#[from] super::record::RecordError),
    /// The output selection does not fit the chain.
    #[error(transparent)]
    Selection(#[from] crate::scene::selection::SelectionError),
}

/// Decodes a HEADER payload of format `version` (1 to 4) and checks its output selection
/// against its bead count.
pub(crate) fn decode_header(version: u32, payload: &[u8]) -> Result<Header, HeaderError> {
    let h = if version >= 4 {
        super::header4::header_from_record(decode_exact(payload)?)?
    } else if version == 3 {
        let o: HeaderV3 = decode_exact(payload)?;
        let sc = o.scene;
        Header {
            format_version: o.format_version,
            crate_version: o.crate_version,
            scene: Scene {
                units: units_from_description(&sc.description),
                name: sc.name,
                description: sc.description,
                chain: sc.chain,
                u0: sc.u0,
                v0: sc.v0,
                run: sc.run,
                seed: sc.seed,
            },
            engine: o.engine,
            method: o.method,
            rtol: o.rtol,
            atol: o.atol,
            seed: o.seed,
            n_beads: o.n_beads,
            created_by: o.created_by,
            output: o.output,
            build_commit: None,
            created_at: None,
        }
    } else {
        let o: HeaderV2 = decode_exact(payload)?;
        Header {
            format_version: o.format_version,
            crate_version: o.crate_version,
            scene: o.scene.upgrade(),
            engine: o.engine,
            method: o.method,
            rtol: o.rtol,
            atol: o.atol,
            seed: o.seed,
            n_beads: o.n_beads,
            created_by: o.created_by,
            output: Selection::default(),
            build_commit: None,
            created_at: None,
        }
    };
    h.output.check(h.n_beads)?;
    Ok(h)
}

/// Reads only the HEADER of the snapshot (or unfinished temporary file) at `path`: magic,
/// version, section header, checksum, payload. `resume` uses it to learn the output selection
/// of the run it continues.
pub fn read_header(path: &Path) -> Result<Header, SnapshotError> {
    let io = |action: &str, e: std::io::Error| SnapshotError::Io {
        path: path.to_path_buf(),
        action: action.to_string(),
        source: e,
    };
    let mut f = std::fs::File::open(path).map_err(|e| io("opening snapshot", e))?;
    let file_len = f.metadata().map_err(|e| io("reading file size", e))?.len();
    let mut pre = [0u8; (PREAMBLE_LEN + SECTION_HEADER_LEN) as usize];
    f.read_exact(&mut pre)
        .map_err(|e| io("reading the HEADER", e))?;
    if pre[..8] != MAGIC {
        return Err(SnapshotError::NotSnapshot {
            path: path.to_path_buf(),
        });
    }
    let version = u32::from_le_bytes([pre[8], pre[9], pre[10], pre[11]]);
    if version == 0 || version > super::FORMAT_VERSION {
        return Err(SnapshotError::UnsupportedVersion {
            path: path.to_path_buf(),
            found: version,
        });
    }
    let tag = u32::from_le_bytes(pre[12..16].try_into().expect("4 bytes"));
    let len = u64::from_le_bytes(pre[16..24].try_into().expect("8 bytes"));
    let crc = u32::from_le_bytes(pre[24..28].try_into().expect("4 bytes"));
    let corrupt = |detail: String| SnapshotError::Corrupt {
        path: path.to_path_buf(),
        section: "HEADER".into(),
        offset: PREAMBLE_LEN,
        detail,
    };
    if tag != TAG_HEADER || len > file_len.saturating_sub(PREAMBLE_LEN + SECTION_HEADER_LEN) {
        return Err(corrupt(format!(
            "tag {tag:#010x} with {len} bytes is not a whole HEADER"
        )));
    }
    let mut payload = vec![0u8; len as usize];
    f.read_exact(&mut payload)
        .map_err(|e| io("reading the HEADER", e))?;
    let mut h = section_hasher(tag, len);
    h.update(&payload);
    if h.finalize() != crc {
        return Err(SnapshotError::ChecksumMismatch {
            path: path.to_path_buf(),
            section: "HEADER".into(),
            offset: PREAMBLE_LEN,
        });
    }
    decode_header(version, &payload).map_err(|e| corrupt(e.to_string()))
}
