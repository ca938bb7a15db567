//! `bodies.csv`: one row per elastic body (solid group) at each output
//! (`analysis::bodies`), flushed as written. Vectors have three components (z = 0 in 2D;
//! omega has only z in 2D).

use std::fs::File;
use std::io::{self, BufWriter, Write};
use std::path::Path;

use crate::analysis::bodies::BodyRow;

/// The header line (without the newline).
pub const BODIES_HEADER: &str =
    "step,time,group,cx,cy,cz,vx,vy,vz,omega_x,omega_y,omega_z,size_ratio,rg_ratio";

/// The open CSV file.
pub struct BodiesCsv {
    w: BufWriter<File>,
}

impl BodiesCsv {
    /// Create (truncate) the file and write the header, or, continuing a run (`append`),
    /// open it at its end.
    pub fn open(path: &Path, append: bool) -> io::Result<BodiesCsv> {
        Ok(BodiesCsv {
            w: super::open_csv(path, BODIES_HEADER, append)?,
        })
    }

    /// Append the rows of one output and flush.
    pub fn write(&mut self, step: u64, time: f64, rows: &[BodyRow]) -> io::Result<()> {
        for r in rows {
            let b = &r.body;
            let (c, v, w) = (b.centroid, b.velocity, b.omega);
            writeln!(
                self.w,
                "{step},{time},{},{},{},{},{},{},{},{},{},{},{},{}",
                b.group,
                c[0],
                c[1],
                c[2],
                v[0],
                v[1],
                v[2],
                w[0],
                w[1],
                w[2],
                r.size_ratio,
                r.rg_ratio
            )?;
        }
        self.w.flush()
    }
}
