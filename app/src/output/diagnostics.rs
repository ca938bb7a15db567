//! `diagnostics.csv`: one row of `Diagnostics` per output time, flushed as written.

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::Path;

use meshfree_core::solver::Diagnostics;

/// The header line (without the newline).
pub const CSV_HEADER: &str = "step,time,dt,kinetic_energy,max_speed,density_error,\
momentum_x,momentum_y,momentum_z,fluid,solid,boundary";

/// One CSV row (without the newline).
pub fn csv_row(d: &Diagnostics) -> String {
    format!(
        "{},{},{},{},{},{},{},{},{},{},{},{}",
        d.step,
        d.time,
        d.dt,
        d.kinetic_energy,
        d.max_speed,
        d.density_error,
        d.momentum[0],
        d.momentum[1],
        d.momentum[2],
        d.fluid,
        d.solid,
        d.boundary
    )
}

/// The open CSV file.
pub struct DiagnosticsCsv {
    w: BufWriter<File>,
}

impl DiagnosticsCsv {
    /// Create (truncate) the file and write the header, or, continuing a run (`append`),
    /// open it at its end.
    pub fn open(path: &Path, append: bool) -> io::Result<DiagnosticsCsv> {
        Ok(DiagnosticsCsv {
            w: super::open_csv(path, CSV_HEADER, append)?,
        })
    }

    /// Append a row and flush.
    pub fn write(&mut self, d: &Diagnostics) -> io::Result<()> {
        writeln!(self.w, "{}", csv_row(d))?;
        self.w.flush()
    }
}
