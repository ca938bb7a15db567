//! `<monitor>.csv` (default `forces.csv`): one row per sample of a force monitor
//! (`meshfree_core::monitor`), flushed as written.

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::Path;

use meshfree_core::monitor::ForceSample;

/// The header line (without the newline). Fz is zero in 2D.
pub const FORCES_HEADER: &str = "t,Fx,Fy,Fz,Cd,Cl";

/// The open CSV file.
pub struct ForcesCsv {
    w: BufWriter<File>,
}

impl ForcesCsv {
    /// Create (truncate) the file and write the header, or, continuing a run (`append`),
    /// open it at its end.
    pub fn open(path: &Path, append: bool) -> io::Result<ForcesCsv> {
        Ok(ForcesCsv {
            w: super::open_csv(path, FORCES_HEADER, append)?,
        })
    }

    /// Append a row and flush.
    pub fn write(&mut self, s: &ForceSample) -> io::Result<()> {
        let f = s.force;
        writeln!(
            self.w,
            "{},{},{},{},{},{}",
            s.t, f[0], f[1], f[2], s.cd, s.cl
        )?;
        self.w.flush()
    }
}
