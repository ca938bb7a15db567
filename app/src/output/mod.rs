//! Run output: binary VTK particle files with a `.pvd` series for ParaView (`vtk`) or
//! particle CSV (`particles_csv`), written by the writer thread (`writer`); the diagnostics
//! CSV (`diagnostics`), the force monitors' CSV (`forces_csv`), the elastic bodies' CSV
//! (`bodies_csv`), the floating bodies' (`floating_csv`), the open boundaries' (`open_csv`) and the JSON run summary (`summary`). A finished run's frames are read back
//! by `frames` (its VTU files by `vtu_read`) for `render DIR` and `view DIR`.
pub mod bodies_csv;
pub mod checkpoint;
pub mod diagnostics;
pub mod files;
pub mod floating_csv;
pub mod forces_csv;
pub mod frames;
pub mod open_csv;
pub mod particles_csv;
pub mod summary;
pub mod vtk;
pub mod vtu_read;
pub mod writer;

pub use bodies_csv::BodiesCsv;
pub use diagnostics::DiagnosticsCsv;
pub use floating_csv::FloatingCsv;
pub use forces_csv::ForcesCsv;
pub use frames::{RecordedFrame, RecordedRun};
pub use open_csv::OpenCsv;
pub use particles_csv::{read_particles_csv, write_particles_csv};
pub use summary::{RunStatus, RunSummary, Timing};
pub use vtk::{write_vtu, Compression, PvdSeries, VtuWriter};
pub use vtu_read::read_vtu;

pub(crate) use files::write_atomic;

/// Open one of a run's CSV files: created with its `header` line, or, where the run
/// continues from a checkpoint (`append`), opened at its end (`crate::resume` cut it back
/// to the checkpoint's length first). A new one is created anew: a file or link already
/// at its name is refused, never followed (`files::create_new`).
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
    let mut w = std::io::BufWriter::new(files::create_new(path)?);
    writeln!(w, "{header}")?;
    w.flush()?;
    Ok(w)
}
