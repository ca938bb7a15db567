//! A driven object's time series (`motion.series`): its CSV file read once with the scene
//! (`load_all`), checked (a header of known columns, increasing times from at or before 0,
//! finite numbers), made relative to t = 0, and laid out as the solver's knots
//! (`Setup::motion_series`, `MF_SERIES_STRIDE` numbers a knot; `table`). The interpolation
//! between knots is `MfMotion::series_at` (twin `motion_series_at`).

use std::sync::{Arc, OnceLock};

use super::ctx::Ctx;
use super::format::{Interpolation, Motion, Series, Wall};
use super::geometry::{Base, ASSETS};
use super::scheme::SceneFile;
use super::SceneError;
use crate::physics::params::{MfMotion, MF_SERIES_STRIDE};

/// The largest series file read \[bytes\]: 10^6 rows of five numbers.
pub const MAX_BYTES: u64 = 64 << 20;

const STRIDE: usize = MF_SERIES_STRIDE as usize;

/// A series as read: its knots (t, s_x, s_y, s_z, theta; each column 0 at t = 0) and the
/// file's bytes (copied into a run's directory, `Scene::with_surface_copies`).
#[derive(Clone, Debug)]
pub struct Knots {
    pub knots: Vec<f64>,
    /// Whether the file has an `angle` column.
    pub turns: bool,
    pub bytes: Vec<u8>,
}

impl Knots {
    pub fn count(&self) -> usize {
        self.knots.len() / STRIDE
    }

    /// \[T\] the last row's time.
    pub fn end(&self) -> f64 {
        self.knots[(self.count() - 1) * STRIDE]
    }
}

/// The knots of a `Series` (set once by `load_all`, when the scene is read). Equal whatever
/// it holds and not serialised: the scene's text is the series' identity.
#[derive(Clone, Default)]
pub struct Loaded(OnceLock<Arc<Knots>>);

impl Loaded {
    pub fn get(&self) -> Option<&Knots> {
        self.0.get().map(|k| &**k)
    }

    /// Holding `knots` alone (a fresh cell: an earlier one, shared by a clone, stays).
    fn hold(knots: Knots) -> Loaded {
        let l = Loaded::default();
        let _ = l.0.set(Arc::new(knots));
        l
    }
}

impl PartialEq for Loaded {
    fn eq(&self, _: &Loaded) -> bool {
        true
    }
}

impl std::fmt::Debug for Loaded {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.get() {
            Some(k) => write!(f, "Loaded({} knots)", k.count()),
            None => write!(f, "Loaded(none)"),
        }
    }
}

/// The series of the scene's driven objects with the field that holds each
/// (`walls[1].motion.series`), solids first, then walls: `driven_objects`' order.
pub fn series_of(s: &SceneFile) -> Vec<(String, &Series)> {
    fn law(m: Option<&Motion>) -> Option<&Series> {
        match m {
            Some(Motion::Law(l)) => l.series.as_deref(),
            _ => None,
        }
    }
    let solids =
        s.solids.iter().enumerate().filter_map(|(i, o)| {
            law(o.motion()).map(|r| (format!("solids[{i}].motion.series"), r))
        });
    let walls = s
        .walls
        .iter()
        .enumerate()
        .filter_map(|(i, w)| law(w.motion()).map(|r| (format!("walls[{i}].motion.series"), r)));
    solids.chain(walls).collect()
}

/// The knots a motion follows besides its laws: its series file's, or the irregular sea
/// its wave maker makes (`make_all`); None where it has neither.
pub fn knots_of(m: &Motion) -> Option<&Knots> {
    let Motion::Law(l) = m else {
        return None;
    };
    let series = l.series.as_ref().and_then(|r| r.loaded.get());
    series.or_else(|| l.wave.as_ref().and_then(|w| w.made.get()))
}

/// The series of the scene's inlets with the field that holds each
/// (`open_boundaries[0].series`), in their order.
pub fn inlet_series_of(s: &SceneFile) -> Vec<(String, &Series)> {
    (s.open_boundaries.iter().enumerate())
        .filter_map(|(b, o)| {
            let r = o.series.as_deref()?;
            Some((format!("open_boundaries[{b}].series"), r))
        })
        .collect()
}

/// The knots of every driven motion of `s` (`knots_of`), one object's after another's in
/// `driven_objects`' order, then every inlet's (`Setup::motion_series`;
/// `MfMotion::series_first` and `MfOpen::series_first` count them the same way: the
/// motions' `motion_knots`, then the inlets').
pub(crate) fn table(s: &SceneFile) -> Vec<f64> {
    let motions = super::driven_objects(s).filter_map(|(_, m)| knots_of(m));
    let inlets = inlet_series_of(s)
        .into_iter()
        .filter_map(|(_, r)| r.loaded.get());
    motions
        .chain(inlets)
        .flat_map(|k| k.knots.iter().copied())
        .collect()
}

/// The knots of the driven motions of `s`: where the inlets' start in `table`.
pub(crate) fn motion_knots(s: &SceneFile) -> usize {
    super::driven_objects(s)
        .filter_map(|(_, m)| knots_of(m))
        .map(Knots::count)
        .sum()
}

/// The largest number of knots an irregular sea's record may have (80 MB).
pub const MAX_MADE_KNOTS: usize = 2_000_000;

/// Makes the paddle record of every irregular wave maker of `s` (`wave_spectrum`) for its
/// end, spacing and gravity, after the checks (`validate`) passed; then refuses a paddle
/// the record would move out of the domain, or a record longer than `MAX_MADE_KNOTS`.
pub(in crate::scene) fn make_all(s: &mut SceneFile, origin: &str) -> Result<(), SceneError> {
    let c = Ctx::new(origin, s.dimension as usize);
    let (g, end, dx) = (
        super::wave::gravity(s),
        s.time.end,
        s.discretisation.spacing,
    );
    let domain = (s.domain.min[0], s.domain.max[0]);
    let walls = s.walls.iter_mut().enumerate().filter_map(|(i, w)| {
        let span = match &*w {
            Wall::Box { min, max, .. } => Some((min.clone(), max.clone())),
            _ => None,
        };
        w.motion_mut()
            .map(|m| (format!("walls[{i}].motion.wave"), span, m))
    });
    for (field, span, m) in walls {
        let Motion::Law(l) = m else { continue };
        let ramp = l.ramp;
        let Some(w) = l.wave.as_mut().filter(|w| w.spectrum.is_some()) else {
            continue;
        };
        let parts = w.components(g, 10.0 * dx);
        if parts.is_empty() {
            return Err(c.err(
                format!("{field}.spectrum"),
                "every component of the sea is shorter than 10 particle spacings: refine the \
                 spacing or lengthen the period",
            ));
        }
        let f_max = parts.iter().map(|p| p.f).fold(0.0, f64::max);
        let count = end * f_max * 40.0;
        if count > MAX_MADE_KNOTS as f64 {
            return Err(c.err(
                format!("{field}.spectrum"),
                format!(
                    "the paddle's record to t = {end} would hold {count:.0} knots, over the \
                     {MAX_MADE_KNOTS} a sea may have: shorten the run or lengthen the period"
                ),
            ));
        }
        let knots = w.knots(&parts, ramp, end);
        // The paddle's travel either way at the still-water level (a flap's top moves more).
        let reach = knots
            .chunks_exact(STRIDE)
            .map(|k| (k[1].abs()).max(w.depth * k[4].tan().abs()))
            .fold(0.0, f64::max);
        let reach = match (&w.hinge, &span) {
            (Some(h), Some((_, hi))) => reach * ((hi[1] - h[1]) / w.depth).max(1.0),
            _ => reach,
        };
        if let Some((lo, hi)) = &span {
            if lo[0] - reach < domain.0 || hi[0] + reach > domain.1 {
                return Err(c.err(
                    field,
                    format!(
                        "the sea moves the paddle up to {reach:.4} either way: from x in [{}, \
                         {}] it leaves the domain [{}, {}]",
                        lo[0], hi[0], domain.0, domain.1
                    ),
                ));
            }
        }
        w.made = Loaded::hold(Knots {
            knots,
            turns: w.paddle == super::format::Paddle::Flap,
            bytes: Vec::new(),
        });
    }
    Ok(())
}

/// The knots of the series `r` at `f`, read (`load_all`) and reaching the run's `end` \[T\];
/// Err naming `f.file` otherwise.
pub(in crate::scene) fn covering<'a>(
    c: &Ctx,
    f: &str,
    r: &'a Series,
    end: f64,
) -> Result<&'a Knots, SceneError> {
    let Some(k) = r.loaded.get() else {
        return Err(c.err(format!("{f}.file"), "the series was not read"));
    };
    if k.end() < end {
        return Err(c.err(
            format!("{f}.file"),
            format!(
                "{:?} ends at t = {}, before the run does (time.end = {end}): the series must \
                 cover the run",
                r.file,
                k.end()
            ),
        ));
    }
    Ok(k)
}

/// Reads every series of `s` from `base`: the first that cannot be read or is not a series
/// is the error. A scene whose dimension is neither 2 nor 3 is left to the checks.
pub(in crate::scene) fn load_all(
    s: &SceneFile,
    origin: &str,
    base: &Base,
) -> Result<(), SceneError> {
    if s.dimension != 2 && s.dimension != 3 {
        return Ok(());
    }
    let c = Ctx::new(origin, s.dimension as usize);
    let motions = series_of(s)
        .into_iter()
        .map(|(f, r)| (f, r, Drives::Motion));
    let inlets = inlet_series_of(s)
        .into_iter()
        .map(|(f, r)| (f, r, Drives::Inlet));
    for (field, r, drives) in motions.chain(inlets) {
        if r.loaded.get().is_none() {
            let f = format!("{field}.file");
            let file = &r.file;
            let bytes = match base {
                Base::Builtin => ASSETS
                    .iter()
                    .find(|(n, _)| *n == file)
                    .map(|(_, b)| b.to_vec())
                    .ok_or_else(|| {
                        c.err(&f, format!("{file:?}: no asset of that name is built in"))
                    })?,
                Base::Dir(dir) => {
                    let path = dir.join(file);
                    super::geometry::read::bytes_at_most(&path, MAX_BYTES, "a series")
                        .map_err(|why| c.err(&f, format!("{}: {why}", path.display())))?
                }
            };
            let knots = parse(&bytes, c.dim, r.interpolation, drives)
                .map_err(|why| c.err(&f, format!("{file:?}: {why}")))?;
            let _ = r.loaded.0.set(Arc::new(Knots { bytes, ..knots }));
        }
    }
    Ok(())
}

/// The columns a motion's series file may have, and the knot's slot each fills.
const COLUMNS: [(&str, usize); 5] = [("t", 0), ("x", 1), ("y", 2), ("z", 3), ("angle", 4)];

/// The columns an inlet's series file has: its velocity's scale \[-\] in the s_x slot.
const SCALE_COLUMNS: [(&str, usize); 2] = [("t", 0), ("scale", 1)];

/// What a series file drives.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Drives {
    /// A driven object (`COLUMNS`): each column's value at t = 0 is taken off.
    Motion,
    /// An inlet's velocity (`SCALE_COLUMNS`): the scale as it is, never negative.
    Inlet,
}

/// The knots of a series file's text: a header naming its columns (`COLUMNS` or
/// `SCALE_COLUMNS` as `drives` says, separated by commas, or by spaces or tabs), then one row
/// of numbers a line; `#` starts a comment. A motion's columns are taken relative to t = 0
/// (interpolated as `interpolation` says). Err with the reason, naming the line.
pub fn parse(
    bytes: &[u8],
    dim: usize,
    interpolation: Interpolation,
    drives: Drives,
) -> Result<Knots, String> {
    let columns: &[(&str, usize)] = match drives {
        Drives::Motion => &COLUMNS,
        Drives::Inlet => &SCALE_COLUMNS,
    };
    let names = match drives {
        Drives::Motion => "t, x, y, z (3D) and angle",
        Drives::Inlet => "t and scale",
    };
    let text = std::str::from_utf8(bytes).map_err(|_| "not a text file (UTF-8)".to_string())?;
    let cells = |line: &str| -> Vec<String> {
        let line = line.split('#').next().unwrap_or("");
        if line.contains(',') {
            line.split(',').map(|c| c.trim().to_string()).collect()
        } else {
            line.split_whitespace().map(str::to_string).collect()
        }
    };
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, cells(l)))
        .filter(|(_, c)| !(c.is_empty() || c.len() == 1 && c[0].is_empty()));
    let (hl, header) = lines.next().ok_or(format!(
        "no header: the first line names the columns, {names}"
    ))?;
    let mut slots = Vec::new();
    for name in &header {
        let low = name.to_ascii_lowercase();
        let Some(&(_, slot)) = columns.iter().find(|(n, _)| *n == low) else {
            return Err(format!(
                "line {hl}: column {name:?} is none of {names} (the first line names the \
                 columns)"
            ));
        };
        if slots.contains(&slot) {
            return Err(format!("line {hl}: column {name:?} is given twice"));
        }
        if slot == 3 && dim == 2 {
            return Err(format!("line {hl}: a 2D scene has no z column"));
        }
        slots.push(slot);
    }
    if !slots.contains(&0) {
        return Err(format!("line {hl}: no t column (the time [T] of each row)"));
    }
    if slots.len() < 2 {
        return Err(match drives {
            Drives::Motion => format!(
                "line {hl}: only a t column: give x, y{} or angle",
                if dim == 3 { ", z" } else { "" }
            ),
            Drives::Inlet => format!("line {hl}: only a t column: give scale"),
        });
    }
    let mut knots = Vec::new();
    let mut last: Option<f64> = None;
    for (ln, row) in lines {
        if row.len() != slots.len() {
            return Err(format!(
                "line {ln}: {} numbers, where the header names {} columns",
                row.len(),
                slots.len()
            ));
        }
        let mut k = [0.0; STRIDE];
        for (cell, &slot) in row.iter().zip(&slots) {
            let v: f64 = cell
                .parse()
                .map_err(|_| format!("line {ln}: {cell:?} is not a number"))?;
            if !v.is_finite() {
                return Err(format!("line {ln}: {cell:?} is not a finite number"));
            }
            if drives == Drives::Inlet && slot == 1 && v < 0.0 {
                return Err(format!(
                    "line {ln}: the scale {v} is negative: an inlet's flow cannot turn back"
                ));
            }
            k[slot] = v;
        }
        if let Some(t) = last {
            if k[0] <= t {
                return Err(format!(
                    "line {ln}: t = {} is not after the row before's {t}: the times must increase",
                    k[0]
                ));
            }
        }
        last = Some(k[0]);
        knots.extend_from_slice(&k);
    }
    let n = knots.len() / STRIDE;
    if n < 2 {
        return Err("fewer than two rows: a series needs at least two times".into());
    }
    if knots[0] > 0.0 {
        return Err(format!(
            "the first row's t = {} is after 0: the series must start at or before t = 0",
            knots[0]
        ));
    }
    if drives == Drives::Inlet {
        return Ok(Knots {
            knots,
            turns: false,
            bytes: Vec::new(),
        });
    }
    // Relative to t = 0: the object is where the scene puts it then.
    let m = MfMotion {
        series_count: n as i32,
        series_cubic: (interpolation == Interpolation::Cubic) as i32,
        ..Default::default()
    };
    let at0 = m.series_at(&knots, 0.0);
    let zero = [at0.s[0], at0.s[1], at0.s[2], at0.q];
    for k in knots.chunks_exact_mut(STRIDE) {
        for (v, z) in k[1..].iter_mut().zip(zero) {
            *v -= z;
        }
    }
    Ok(Knots {
        knots,
        turns: slots.contains(&4),
        bytes: Vec::new(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn knots(text: &str, dim: usize) -> Result<Knots, String> {
        parse(text.as_bytes(), dim, Interpolation::Linear, Drives::Motion)
    }

    #[test]
    fn a_record_of_positions_is_taken_from_where_it_is_at_t_0() {
        let k = knots(
            "# paddle\nt, x, angle\n-1, 0.25, 0.5\n1, 0.45, 0.7\n3, 0.35, 0.3\n",
            2,
        )
        .unwrap();
        assert_eq!(k.count(), 3);
        assert!(k.turns);
        // At t = 0 x = 0.35 and angle = 0.6 (halfway): taken off every row.
        let want = [
            -1.0, -0.1, 0.0, 0.0, -0.1, 1.0, 0.1, 0.0, 0.0, 0.1, 3.0, 0.0, 0.0, 0.0, -0.3,
        ];
        for (a, b) in k.knots.iter().zip(want) {
            assert!((a - b).abs() < 1e-12, "{:?}", k.knots);
        }
        assert_eq!(k.end(), 3.0);
    }

    #[test]
    fn whitespace_separates_as_commas_do() {
        let a = knots("t x\n0 0\n1 0.5\n", 2).unwrap();
        let b = knots("t,x\n0,0\n1,0.5\n", 2).unwrap();
        assert_eq!(a.knots, b.knots);
        assert!(!a.turns);
    }

    #[test]
    fn bad_files_say_which_line_and_why() {
        for (text, dim, why) in [
            ("", 2, "no header"),
            ("t,q\n0,1\n", 2, "column \"q\""),
            ("t,x,x\n", 2, "given twice"),
            ("t,z\n0,0\n1,1\n", 2, "no z column"),
            ("x,y\n0,0\n", 2, "no t column"),
            ("t\n0\n1\n", 2, "only a t column"),
            ("t,x\n0,0\n1\n", 2, "line 3: 1 numbers"),
            ("t,x\n0,0\n1,abc\n", 2, "line 3: \"abc\" is not a number"),
            ("t,x\n0,0\n1,inf\n", 2, "not a finite number"),
            ("t,x\n0,0\n1,1\n1,2\n", 2, "line 4: t = 1 is not after"),
            ("t,x\n0,0\n", 2, "fewer than two rows"),
            ("t,x\n0.5,0\n1,1\n", 3, "start at or before t = 0"),
        ] {
            let e = knots(text, dim).err().unwrap_or_default();
            assert!(e.contains(why), "{text:?}: {e}");
        }
        let e = parse(&[0xff, 0xfe], 2, Interpolation::Linear, Drives::Motion).unwrap_err();
        assert!(e.contains("UTF-8"), "{e}");
    }
}
