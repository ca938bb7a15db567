//! Run output: binary VTK particle files with a `.pvd` series for ParaView (`vtk`) or
//! particle CSV (`particles_csv`), written by the writer thread (`writer`); the diagnostics
//! CSV (`diagnostics`), the force monitors' CSV (`forces_csv`), the elastic bodies' CSV
//! (`bodies_csv`) and the JSON run summary (`summary`).
pub mod bodies_csv;
pub mod checkpoint;
pub mod diagnostics;
pub mod forces_csv;
pub mod particles_csv;
pub mod summary;
pub mod vtk;
pub mod writer;

pub use bodies_csv::BodiesCsv;
pub use diagnostics::DiagnosticsCsv;
pub use forces_csv::ForcesCsv;
pub use particles_csv::{read_particles_csv, write_particles_csv};
pub use summary::{RunStatus, RunSummary, Timing};
pub use vtk::{write_vtu, PvdSeries};

/// Write `bytes` to `path` through a temporary file and a rename, so a reader never sees
/// half a file.
pub(crate) fn write_atomic(path: &std::path::Path, bytes: &[u8]) -> std::io::Result<()> {
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(".tmp");
    let tmp = std::path::PathBuf::from(tmp);
    std::fs::write(&tmp, bytes)?;
    std::fs::rename(&tmp, path)
}

/// Open one of a run's CSV files: created with its `header` line, or, where the run
/// continues from a checkpoint (`append`), opened at its end (`crate::resume` cut it back
/// to the checkpoint's length first).
pub(crate) fn open_csv(
    path: &std::path::Path,
    header: &str,
    append: bool,
) -> std::io::Result<std::io::BufWriter<std::fs::File>> {
    use std::io::Write as _;
    if append {
        let f = std::fs::OpenOptions::new().append(true).open(path)?;
        return Ok(std::io::BufWriter::new(f));
    }
    let mut w = std::io::BufWriter::new(std::fs::File::create(path)?);
    writeln!(w, "{header}")?;
    w.flush()?;
    Ok(w)
}
