//! `open_boundaries.csv`: one row per open boundary (`[[open_boundaries]]`,
//! `meshfree_core::physics::open`) every output interval, flushed as written: the particles
//! and mass \[M\] (per unit depth in 2D) that came in and went out through it since the run
//! began. The fluid a boundary holds back or lets in over an interval is the difference of
//! two rows.

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::Path;

use meshfree_core::physics::open::OpenTally;

/// The header line (without the newline).
pub const OPEN_HEADER: &str = "time,boundary,count_in,mass_in,count_out,mass_out";

/// The open CSV file.
pub struct OpenCsv {
    w: BufWriter<File>,
}

impl OpenCsv {
    /// Create the file and write the header, or, continuing a run (`append`), open it at
    /// its end.
    pub fn open(path: &Path, append: bool) -> io::Result<OpenCsv> {
        Ok(OpenCsv {
            w: super::open_csv(path, OPEN_HEADER, append)?,
        })
    }

    /// The rows of every boundary (the scene's order) at time `t` \[T\], flushed.
    pub fn write(&mut self, t: f64, tally: &[OpenTally]) -> io::Result<()> {
        for (b, o) in tally.iter().enumerate() {
            writeln!(
                self.w,
                "{t},{b},{},{},{},{}",
                o.count_in, o.mass_in, o.count_out, o.mass_out
            )?;
        }
        self.w.flush()
    }
}
