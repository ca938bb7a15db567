//! `<monitor>.csv` (default `forces.csv`): one row per sample of a force monitor
//! (`meshfree_core::measure::monitor`), flushed as written.

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::Path;

use meshfree_core::measure::monitor::ForceSample;

/// The header line (without the newline) of a bluff body's monitor (with reference
/// scales); Fz is zero in 2D. The time column is `time`, as in the other CSV files.
pub const FORCES_HEADER: &str = "time,Fx,Fy,Fz,Cd,Cl";
/// The header of a monitor without reference scales: the force alone.
pub const FORCES_ONLY_HEADER: &str = "time,Fx,Fy,Fz";

/// The open CSV file.
pub struct ForcesCsv {
    w: BufWriter<File>,
    coefficients: bool,
}

impl ForcesCsv {
    /// Create the file and write the header (with the coefficients' columns where the
    /// monitor has reference scales), or, continuing a run (`append`), open it at its end.
    pub fn open(path: &Path, append: bool, coefficients: bool) -> io::Result<ForcesCsv> {
        let header = if coefficients {
            FORCES_HEADER
        } else {
            FORCES_ONLY_HEADER
        };
        Ok(ForcesCsv {
            w: super::open_csv(path, header, append)?,
            coefficients,
        })
    }

    /// Append a row and flush.
    pub fn write(&mut self, s: &ForceSample) -> io::Result<()> {
        let f = s.force;
        write!(self.w, "{},{},{},{}", s.t, f[0], f[1], f[2])?;
        if self.coefficients {
            write!(self.w, ",{},{}", s.cd, s.cl)?;
        }
        writeln!(self.w)?;
        self.w.flush()
    }
}
