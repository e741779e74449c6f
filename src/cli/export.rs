//! `brdfkit export SCENE.toml -o DIR`: the resolved camera, mesh, lights, material and
//! scene a GPU build needs to draw the same frame ([`crate::export`]).

use crate::aov::Aov;
use crate::error::Result;
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct ExportArgs {
    /// The scene file to export.
    pub scene: PathBuf,
    /// Directory to write into (created if missing; files of the same names are replaced).
    #[arg(short, long)]
    pub output: PathBuf,
    /// The debug output the frame is (a golden entry's aov): recorded in export.json and
    /// scene.toml with the render command that draws it.
    #[arg(long, value_enum)]
    pub aov: Option<Aov>,
}

pub fn run(a: ExportArgs) -> Result<()> {
    let out = crate::export::export(&a.scene, &a.output, a.aov)?;
    for f in &out.files {
        println!("wrote {}", f.display());
    }
    Ok(())
}
