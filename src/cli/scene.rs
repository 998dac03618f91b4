//! `beadchain scene show`: the resolved scene ([`beadchain::scene::show`]).

use clap::{Subcommand, ValueEnum};

/// `beadchain scene ...` subcommands.
#[derive(Subcommand, Debug)]
pub enum SceneCmd {
    /// Print the resolved scene: every per-bead and per-contact value after the builders and
    /// the unit conversion (computer units), as a TOML scene file with explicit arrays that
    /// runs the same chain, or as CSV (one row per bead, with the contact to its right).
    Show {
        /// Scene file (TOML) or preset name (see `beadchain scenes`).
        scene: String,
        /// Output format.
        #[arg(long, value_enum, default_value = "toml")]
        format: ShowFormat,
    },
}

/// Output format of `scene show`.
#[derive(ValueEnum, Clone, Copy, Debug)]
pub enum ShowFormat {
    /// A dimensionless scene file (parses back to the same scene).
    Toml,
    /// One row per bead: bead,mass,u0,v0,force,exponent,prefactor,precompression,restitution.
    Csv,
}

/// Runs a `scene` subcommand; returns the exit code.
pub fn cmd_scene(cmd: SceneCmd) -> anyhow::Result<i32> {
    match cmd {
        SceneCmd::Show { scene, format } => {
            let s = super::common::load_scene(&scene)?;
            let text = match format {
                ShowFormat::Toml => beadchain::scene::show::to_toml(&s),
                ShowFormat::Csv => beadchain::scene::show::to_csv(&s),
            };
            out!("{text}");
            Ok(0)
        }
    }
}
