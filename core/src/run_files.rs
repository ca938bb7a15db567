//! The names of the files a run writes in its output directory, in one place: the app's
//! writer names its files from here, and scene validation refuses an object whose name
//! would become one of them (a force monitor writes `<name>.csv` beside them: named
//! `diagnostics`, its rows and the diagnostics' would interleave in one file; issue #52).

/// The diagnostics, one row per output step.
pub const DIAGNOSTICS: &str = "diagnostics.csv";
/// Cluster counts (`[output] clusters`).
pub const CLUSTERS: &str = "clusters.csv";
/// The solid bodies' motion.
pub const BODIES: &str = "bodies.csv";
/// The floating rigid bodies' pose, velocities and loads.
pub const FLOATING: &str = "floating.csv";
/// The open boundaries' particles and mass in and out.
pub const OPEN_BOUNDARIES: &str = "open_boundaries.csv";
/// Void fractions (`[output] voids`).
pub const VOIDS: &str = "voids.csv";
/// `[[probes]]` samples, all probes in one file.
pub const PROBES: &str = "probes.csv";
/// `[[gauges]]` samples, all gauges in one file.
pub const GAUGES: &str = "gauges.csv";
/// The frames' index for ParaView.
pub const SERIES: &str = "particles.pvd";
/// The run's summary.
pub const SUMMARY: &str = "summary.json";
/// The copy of the scene the run read.
pub const SCENE: &str = "scene.toml";
/// The checkpoint.
pub const CHECKPOINT: &str = "checkpoint.bin";

/// Every file above.
pub const FILES: [&str; 12] = [
    DIAGNOSTICS,
    CLUSTERS,
    BODIES,
    FLOATING,
    OPEN_BOUNDARIES,
    VOIDS,
    PROBES,
    GAUGES,
    SERIES,
    SUMMARY,
    SCENE,
    CHECKPOINT,
];

/// The frames are `particles_NNNNN.vtu` (or `.csv`), NNNNN the frame's number.
pub const FRAME_PREFIX: &str = "particles_";
/// A decomposed run's checkpoint pieces are `checkpoint-step<S>-rank<R>of<N>.bin`.
pub const CHECKPOINT_PIECE_PREFIX: &str = "checkpoint-";

/// The copies of the scene's surface files are `surface-<N>.<ext>` (`scene::geometry`).
pub const SURFACE_PREFIX: &str = "surface-";

/// The copy of the scene's surface file number `index`, of extension `ext` (`stl`, `csv`).
pub fn surface_file(index: usize, ext: &str) -> String {
    format!("{SURFACE_PREFIX}{index}.{ext}")
}

/// The copies of the scene's motion series files are `motion-<N>.csv` (`scene::motion_series`).
pub const MOTION_PREFIX: &str = "motion-";

/// The copy of the scene's motion series file number `index`.
pub fn motion_file(index: usize) -> String {
    format!("{MOTION_PREFIX}{index}.csv")
}

/// The copies of the scene's inlets' series files are `inflow-<N>.csv`.
pub const INFLOW_PREFIX: &str = "inflow-";

/// The copy of the scene's inlet series file number `index`.
pub fn inflow_file(index: usize) -> String {
    format!("{INFLOW_PREFIX}{index}.csv")
}

/// The index of a surface copy's name (`surface_file`'s inverse): digits after the prefix,
/// then an extension of letters.
pub fn surface_index(name: &str) -> Option<usize> {
    copy_index(name, SURFACE_PREFIX)
}

/// The index of a motion series copy's name (`motion_file`'s inverse).
pub fn motion_index(name: &str) -> Option<usize> {
    copy_index(name, MOTION_PREFIX)
}

/// The index of an inlet series copy's name (`inflow_file`'s inverse).
pub fn inflow_index(name: &str) -> Option<usize> {
    copy_index(name, INFLOW_PREFIX)
}

fn copy_index(name: &str, prefix: &str) -> Option<usize> {
    let (digits, ext) = name.strip_prefix(prefix)?.split_once('.')?;
    let plain = !digits.is_empty()
        && digits.bytes().all(|b| b.is_ascii_digit())
        && !ext.is_empty()
        && ext.bytes().all(|b| b.is_ascii_alphanumeric());
    plain.then(|| digits.parse().ok()).flatten()
}

/// \[bytes\] the longest name an object may give a file (`<name>.csv` stays well within the
/// 255 bytes every file system takes).
pub const MAX_STEM: usize = 100;

/// The frame file of number `index` with extension `ext` (`vtu`, `csv`).
pub fn frame_file(index: u64, ext: &str) -> String {
    format!("{FRAME_PREFIX}{index:05}.{ext}")
}

/// The file of force monitor `name`.
pub fn monitor_file(name: &str) -> String {
    format!("{name}.csv")
}

/// Whether `stem` (a file name without its extension) is, or may be, one of the run's own
/// files: a name of `FILES` without extension, or one starting with a numbered file's
/// prefix. Compared without case: on a case-insensitive file system (macOS, Windows)
/// `Diagnostics.csv` is `diagnostics.csv`.
pub fn is_reserved(stem: &str) -> bool {
    let s = stem.to_ascii_lowercase();
    FILES
        .iter()
        .any(|f| f.split_once('.').is_some_and(|(base, _)| base == s))
        || s.starts_with(FRAME_PREFIX)
        || s.starts_with(CHECKPOINT_PIECE_PREFIX)
        || s.starts_with(SURFACE_PREFIX)
        || s.starts_with(MOTION_PREFIX)
        || s.starts_with(INFLOW_PREFIX)
}

/// Why `name` may not be the stem of a file the run writes for an object (a force
/// monitor), or None where it may: a plain name of 1 to `MAX_STEM` ASCII letters, digits,
/// '-' and '_' (no path separator, no `..`, no leading dot, no control character), not
/// one of the run's own files (`is_reserved`).
pub fn stem_problem(name: &str) -> Option<String> {
    let plain = !name.is_empty()
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_');
    if !plain || name.len() > MAX_STEM {
        return Some(format!(
            "must be a file name of letters, digits, '-' and '_', 1 to {MAX_STEM} of them (it \
             names the file <name>.csv in the output directory), found {name:?}"
        ));
    }
    if is_reserved(name) {
        let files = FILES.join(", ");
        return Some(format!(
            "{name:?} would name a file the run writes itself ({files}, \
             {FRAME_PREFIX}NNNNN.*, {CHECKPOINT_PIECE_PREFIX}*.bin; compared without case): \
             choose another name"
        ));
    }
    None
}
