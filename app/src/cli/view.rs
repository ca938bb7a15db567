//! The arguments of `meshfree view` and `meshfree render`; the binary's viewer glue
//! (`src/view.rs`) carries them out, which keeps GL out of this library.

use std::path::PathBuf;

use super::named;
use meshfree_core::backend::BackendChoice;
use meshfree_core::solver::Shown;

#[derive(Debug, clap::Args)]
pub struct ViewArgs {
    /// A scene file path or a built-in scene name (simulated live), or a run's output
    /// directory (its recorded frames, played one frame per drawn frame: space pauses, `.`
    /// or the right arrow steps one frame, `,` or the left arrow one back, `<` and `>` (Home,
    /// End) go to the first and the last, and a click or drag on the slider along the
    /// bottom to any; nothing is simulated, and --backend, --steps-per-frame, --out,
    /// --paper-exact and --spacing do not apply).
    pub scene: String,
    /// Where to run the solver.
    #[arg(long, value_parser = named::<BackendChoice>(), default_value = "auto")]
    pub backend: BackendChoice,
    /// The field that colours the particles (press `f` in the window to change it).
    #[arg(long, value_parser = named::<Shown>(), default_value = "speed")]
    pub field: Shown,
    /// Solver steps per drawn frame (`+`/`-` in the window).
    #[arg(long, default_value_t = 10)]
    pub steps_per_frame: u32,
    /// Where the final particles and summary.json go when the window closes
    /// (default: `out/<scene name>`).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Use only the paper's own equations: summation density, forward Euler at a fixed
    /// step, artificial viscosity only, Lennard-Jones walls (docs/reference/paper-scenes.md).
    #[arg(long)]
    pub paper_exact: bool,
    /// Replace the scene's particle spacing (more or fewer particles; the wall strength
    /// follows).
    #[arg(long, value_name = "DX")]
    pub spacing: Option<f64>,
    /// 3D: start with the fluid drawn as a screen-space surface (`s` in the window).
    #[arg(long)]
    pub surface: bool,
    /// Scripted captures and tests: write the window to this PNG after --capture-after drawn
    /// frames, then close it.
    #[arg(long, value_name = "PNG", hide = true)]
    pub capture: Option<PathBuf>,
    /// The drawn frames before --capture.
    #[arg(
        long,
        value_name = "N",
        hide = true,
        default_value_t = 30,
        requires = "capture"
    )]
    pub capture_after: u32,
}

impl ViewArgs {
    /// `ViewOptions::screenshot_after_frames` of --capture.
    pub fn capture(&self) -> Option<(u32, PathBuf)> {
        self.capture.clone().map(|p| (self.capture_after.max(1), p))
    }
}

#[derive(Debug, clap::Args)]
pub struct RenderArgs {
    /// A scene file path or a built-in scene name (simulated to the times drawn), or a run's
    /// output directory (`meshfree run`'s: its frames, particles.pvd or particles_NNNNN.csv,
    /// are drawn as written, nothing is simulated; --figures, --t-end, --spacing,
    /// --paper-exact, --steps-per-frame and --host-copy do not apply).
    pub scene: String,
    /// Where to run the solver.
    #[arg(long, value_parser = named::<BackendChoice>(), default_value = "auto")]
    pub backend: BackendChoice,
    /// Render at this simulated time, in the scene's time unit (seconds for SI scenes); of a
    /// run's directory, the frame nearest T [default: the start; of a run's directory, its
    /// last frame].
    #[arg(long, value_name = "T", conflicts_with = "frames")]
    pub at: Option<f64>,
    /// Render N frames evenly spaced up to the scene's end time (or --t-end), as
    /// OUT_0000.png, OUT_0001.png, ...; of a run's directory, N of its frames evenly spaced
    /// from the first to the last.
    #[arg(long, value_name = "N")]
    pub frames: Option<u32>,
    /// Render at each of the scene's figure moments (`time.figures`: the moments of the
    /// paper's figures) into the directory --out, as SCENE_tT.png.
    #[arg(long, conflicts_with_all = ["at", "frames"])]
    pub figures: bool,
    /// End time for --frames (and --figures: later moments are skipped), replacing the
    /// scene's.
    #[arg(long, value_name = "T")]
    pub t_end: Option<f64>,
    /// The PNG to write (with --frames, the stem of the sequence; with --figures, a
    /// directory). Not needed with --movie.
    #[arg(long, value_name = "PNG", required_unless_present = "movie")]
    pub out: Option<PathBuf>,
    /// Of a run's directory: encode its frames (all of them, or --frames N) into this video
    /// through an installed `ffmpeg` (H.264 in an .mp4, or whatever the name's extension
    /// tells ffmpeg), instead of PNGs.
    #[arg(long, value_name = "VIDEO", conflicts_with = "at")]
    pub movie: Option<PathBuf>,
    /// Frames per second of --movie.
    #[arg(long, default_value_t = 30, requires = "movie", value_parser = clap::value_parser!(u32).range(1..=240))]
    pub fps: u32,
    /// Image size as WIDTHxHEIGHT.
    #[arg(long, default_value = "1280x720", value_parser = parse_size)]
    pub size: (u32, u32),
    /// The field that colours the particles.
    #[arg(long, value_parser = named::<Shown>(), default_value = "speed")]
    pub field: Shown,
    /// Draw boundary (wall) particles too (hidden by default in 3D, as in the paper).
    #[arg(long)]
    pub show_boundary: bool,
    /// Replace the scene's particle spacing (more or fewer particles; the wall strength
    /// follows).
    #[arg(long, value_name = "DX")]
    pub spacing: Option<f64>,
    /// Use only the paper's own equations: summation density, forward Euler at a fixed
    /// step, artificial viscosity only, Lennard-Jones walls (docs/reference/paper-scenes.md).
    #[arg(long)]
    pub paper_exact: bool,
    /// With --frames: solver steps between frames instead of even times, and a timing line
    /// (frames per second, drawing and solver ms, solver slow-down from drawing, the
    /// static-buffer drawing ceiling: the same spheres drawn again as sprites from the
    /// vertex buffers, device-to-host bytes per frame) and its JSON (`timing-json: {...}`).
    /// With the CUDA backend the spheres come from the GPU's visibility splat from a view's
    /// second frame on (sprites at most 32 pixels across, in perspective).
    #[arg(long, value_name = "K", requires = "frames")]
    pub steps_per_frame: Option<u32>,
    /// 3D: draw the fluid as a screen-space surface (smoothed depth, Fresnel, absorption)
    /// instead of spheres.
    #[arg(long)]
    pub surface: bool,
    /// Draw the viewer's panel (time, particles, steps/s, frames/s, field and range, what
    /// is shown) as the live window does.
    #[arg(long)]
    pub panel: bool,
    /// Colour range LO,HI instead of the visible particles' (with the CUDA backend nothing
    /// then comes back from the device to draw a frame).
    #[arg(long, value_name = "LO,HI", value_parser = parse_range)]
    pub range: Option<(f32, f32)>,
    /// Draw from a host copy of the particles (read back, then uploaded: the CPU backend's
    /// path) even with the CUDA backend, instead of filling the vertex buffers on the GPU
    /// (CUDA-OpenGL interop); for comparison.
    #[arg(long)]
    pub host_copy: bool,
}

fn parse_range(s: &str) -> Result<(f32, f32), String> {
    let (lo, hi) = s
        .split_once(',')
        .ok_or_else(|| format!("`{s}`: expected LO,HI, e.g. 0,2.5"))?;
    match (lo.trim().parse::<f32>(), hi.trim().parse::<f32>()) {
        (Ok(lo), Ok(hi)) if lo.is_finite() && hi.is_finite() && lo < hi => Ok((lo, hi)),
        _ => Err(format!(
            "`{s}`: LO and HI must be finite numbers with LO < HI"
        )),
    }
}

fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once('x')
        .ok_or_else(|| format!("`{s}`: expected WIDTHxHEIGHT, e.g. 1280x720"))?;
    let parse = |v: &str| v.parse::<u32>().ok().filter(|&n| (16..=16384).contains(&n));
    match (parse(w), parse(h)) {
        (Some(w), Some(h)) => Ok((w, h)),
        _ => Err(format!(
            "`{s}`: width and height must be integers from 16 to 16384"
        )),
    }
}
