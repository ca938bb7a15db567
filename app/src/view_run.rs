//! The viewer glue for a finished run (issue #51): `meshfree render DIR` draws the frames a
//! run wrote (`output::frames`) headless, and `meshfree view DIR` steps through them in the
//! window (`Recorded`, a `LiveSource` that serves recorded frames instead of a solver).
//! Nothing is simulated again.

use std::path::{Path, PathBuf};

use anyhow::Context;
use meshfree::bad_input::BadInput;
use meshfree::cli::{RenderArgs, ViewArgs};
use meshfree::output::frames::{kinds, values};
use meshfree::output::RecordedRun;
use meshfree_core::solver::frame;
use meshfree_core::solver::Shown;
use meshfree_viewer::{
    Field, FrameData, LiveSource, Panel, RenderOptions, Status, Timeline, ViewOptions,
};

use crate::view::{field, frame_meta, shown, wall_lines, window_error, WallLines};

/// A run's frames as the viewer draws them: the scene's dimension, domain, particle radius
/// and box walls (gates leave at their removal time), around each frame read.
struct Recorded {
    run: RecordedRun,
    outlines: WallLines,
    /// The frame shown and its index.
    index: usize,
    frame: frame::FrameData,
    /// Fields asked for that the run did not write, said once each (the window draws
    /// them as zero).
    said: Vec<Shown>,
}

impl Recorded {
    fn open(dir: &Path) -> anyhow::Result<Recorded> {
        let run = RecordedRun::open(dir)?;
        Ok(Recorded {
            outlines: wall_lines(&run.scene),
            run,
            index: usize::MAX,
            frame: frame::FrameData::default(),
            said: Vec::new(),
        })
    }

    /// Make frame `k` the one shown (read where it is another).
    fn go(&mut self, k: usize) -> Result<(), BadInput> {
        let k = k.min(self.run.frames.len() - 1);
        if k != self.index {
            self.frame = self.run.read(k)?;
            self.index = k;
        }
        Ok(())
    }

    /// What the error messages call the frame shown.
    fn what(&self) -> String {
        let f = &self.run.frames[self.index];
        format!("{} (t = {})", f.path.display(), f.time)
    }

    /// The shown frame for the viewer, coloured by `f`.
    fn fill(&self, f: Shown, out: &mut FrameData) -> Result<(), BadInput> {
        let p = self.run.scene.params();
        frame_meta(&p, self.frame.time, &self.outlines, out);
        out.positions.clear();
        out.positions.extend_from_slice(&self.frame.position);
        out.kinds = kinds(&self.frame);
        out.values = values(&self.frame, f, &self.what())?;
        Ok(())
    }
}

impl LiveSource for Recorded {
    /// `steps` recorded frames on, stopping at the last.
    fn advance(&mut self, steps: u32) -> Result<(), String> {
        let k = self.index.saturating_add(steps as usize);
        self.go(k).map_err(|e| e.0)
    }

    fn frame(&mut self, f: Field, out: &mut FrameData) {
        let f = shown(f);
        if let Err(e) = self.fill(f, out) {
            // A field the run did not write: drawn as zero, said once.
            if !self.said.contains(&f) {
                meshfree::errln!("{e}; drawn as zero");
                self.said.push(f);
            }
            out.values.clear();
            out.values.resize(out.positions.len(), 0.0);
        }
    }

    /// The frame's time; its index as the step.
    fn status(&self) -> Status {
        Status {
            time: self.frame.time,
            step: self.index as u64,
            particles: self.frame.len,
        }
    }

    fn reset(&mut self) -> Result<(), String> {
        self.go(0).map_err(|e| e.0)
    }

    fn timeline(&self) -> Option<Timeline> {
        let frames = &self.run.frames;
        Some(Timeline {
            frame: self.index.min(frames.len() - 1),
            frames: frames.len(),
            times: (frames[0].time, frames[frames.len() - 1].time),
        })
    }

    fn seek(&mut self, k: usize) -> Result<(), String> {
        self.go(k).map_err(|e| e.0)
    }
}

/// Flags of `render` that re-simulate a scene: refused with a run's directory.
fn refuse_scene_flags(a: &RenderArgs) -> Result<(), BadInput> {
    let given = [
        ("--figures", a.figures),
        ("--t-end", a.t_end.is_some()),
        ("--spacing", a.spacing.is_some()),
        ("--paper-exact", a.paper_exact),
        ("--steps-per-frame", a.steps_per_frame.is_some()),
        ("--host-copy", a.host_copy),
    ];
    if let Some((flag, _)) = given.iter().find(|(_, on)| *on) {
        return Err(BadInput(format!(
            "{flag} applies to a scene that render simulates, not to a run's directory \
             `{}` (whose frames are drawn as they were written)",
            a.scene
        )));
    }
    Ok(())
}

/// `meshfree render DIR`: the frames of the finished run in DIR, drawn headless: the last
/// one, the one nearest `--at T`, or `--frames N` evenly spaced over the run's frames; with
/// `--movie`, encoded by ffmpeg (all the frames unless `--frames N`).
pub fn render_run(a: RenderArgs) -> anyhow::Result<()> {
    refuse_scene_flags(&a)?;
    // Before anything is read or drawn: is there an encoder?
    if a.movie.is_some() {
        movie::detect()?;
    }
    let mut rec = Recorded::open(Path::new(&a.scene))?;
    let n = rec.run.frames.len();
    let count = a
        .frames
        .map(|c| c.max(1) as usize)
        .or(a.movie.as_ref().map(|_| n));
    let picks: Vec<usize> = match (count, a.at) {
        (Some(count), _) => {
            if count > n {
                meshfree::errln!(
                    "{count} frames asked, the run has {n}: some are drawn more than once"
                );
            }
            rec.run.evenly(count)
        }
        (None, Some(t)) => vec![rec.run.nearest(t)],
        (None, None) => vec![n - 1],
    };
    // Where each image goes as PNG: numbered with a count, else --out itself; none with
    // --movie and no --out.
    let png = |i: usize| -> Option<PathBuf> {
        let out = a.out.as_ref()?;
        Some(match count {
            Some(_) => PathBuf::from(format!("{}_{i:04}.png", out.with_extension("").display())),
            None => out.clone(),
        })
    };
    let f = a.field;
    // The first frame is read and checked before EGL is opened: a missing field or a bad
    // file is said at once, where EGL is missing too.
    let mut frame = FrameData::default();
    rec.go(picks[0])?;
    rec.fill(f, &mut frame)?;
    for path in [a.out.as_ref(), a.movie.as_ref()].into_iter().flatten() {
        if let Some(parent) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
            std::fs::create_dir_all(parent)
                .with_context(|| format!("creating {}", parent.display()))?;
        }
    }
    let started = std::time::Instant::now();
    let mut renderer = meshfree_viewer::HeadlessRenderer::new()?;
    meshfree::errln!(
        "{}: {n} frames in {}; headless OpenGL: {}",
        rec.run.scene.name(),
        rec.run.dir.display(),
        renderer.gl_renderer()
    );
    let mut video = match &a.movie {
        Some(path) => Some(movie::Movie::start(path, a.size, a.fps)?),
        None => None,
    };
    let dim = rec.run.scene.file.dimension;
    for (i, &k) in picks.iter().enumerate() {
        rec.go(k)?;
        rec.fill(f, &mut frame)?;
        let status = rec.status();
        let opts = RenderOptions {
            width: a.size.0,
            height: a.size.1,
            field: field(f),
            range: a.range,
            hide_kinds: [false, false, dim == 3 && !a.show_boundary],
            overlay: vec![format!("{}  t = {:.3}", rec.run.scene.name(), status.time)],
            surface: a.surface,
            panel: a.panel.then_some(Panel {
                status,
                paused: true,
                steps_per_frame: 1,
                steps_per_second: 0.0,
                frames_per_second: 0.0,
                show_help: false,
                timeline: rec.timeline(),
            }),
            ..Default::default()
        };
        let image = renderer.render(&frame, &opts)?;
        if let Some(v) = video.as_mut() {
            v.push(&image)?;
        }
        if let Some(path) = png(i) {
            image
                .save_png(&path)
                .with_context(|| format!("writing {}", path.display()))?;
            meshfree::outln!(
                "wrote {} (t = {:.4}, frame {k} of the run: {})",
                path.display(),
                status.time,
                rec.run.frames[k].path.display()
            )?;
        }
    }
    if let Some(v) = video {
        let path = v.finish()?;
        meshfree::outln!(
            "wrote {} ({} frames at {} frames/s)",
            path.display(),
            picks.len(),
            a.fps
        )?;
    }
    meshfree::errln!(
        "{} images in {:.2} s",
        picks.len(),
        started.elapsed().as_secs_f64()
    );
    Ok(())
}

/// `--movie`: the images piped to an installed ffmpeg as raw RGBA.
mod movie {
    use std::io::Write as _;
    use std::path::{Path, PathBuf};
    use std::process::{Child, Command, Stdio};

    use anyhow::Context as _;

    const MISSING: &str = "--movie needs `ffmpeg` on the PATH (install it: e.g. `apt-get \
        install ffmpeg`, `brew install ffmpeg`); without it, `--frames N --out DIR/f.png` \
        writes the frames as PNGs, which any encoder takes";

    /// Whether ffmpeg answers; an error naming what to install where it does not.
    pub fn detect() -> anyhow::Result<()> {
        let status = Command::new("ffmpeg")
            .arg("-version")
            .stdin(Stdio::null())
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .status();
        match status {
            Ok(s) if s.success() => Ok(()),
            Ok(s) => anyhow::bail!("`ffmpeg -version` failed ({s}): {MISSING}"),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => anyhow::bail!("{MISSING}"),
            Err(e) => anyhow::bail!("starting ffmpeg: {e}: {MISSING}"),
        }
    }

    pub struct Movie {
        child: Child,
        path: PathBuf,
    }

    impl Movie {
        /// ffmpeg reading `w`x`h` RGBA frames at `fps` from its standard input into `path`
        /// (an odd size is cropped by a pixel: H.264's 4:2:0 wants even sides).
        pub fn start(path: &Path, (w, h): (u32, u32), fps: u32) -> anyhow::Result<Movie> {
            let mut cmd = Command::new("ffmpeg");
            cmd.args([
                "-y",
                "-loglevel",
                "error",
                "-f",
                "rawvideo",
                "-pix_fmt",
                "rgba",
            ])
            .args(["-s", &format!("{w}x{h}"), "-r", &fps.to_string(), "-i", "-"]);
            let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
            if matches!(ext, "mp4" | "m4v" | "mov" | "mkv") {
                cmd.args([
                    "-vf",
                    "crop=trunc(iw/2)*2:trunc(ih/2)*2",
                    "-pix_fmt",
                    "yuv420p",
                ]);
            }
            let child = cmd
                .arg(path)
                .stdin(Stdio::piped())
                .spawn()
                .with_context(|| format!("starting ffmpeg for {}", path.display()))?;
            Ok(Movie {
                child,
                path: path.to_path_buf(),
            })
        }

        pub fn push(&mut self, image: &meshfree_viewer::Image) -> anyhow::Result<()> {
            let stdin = self.child.stdin.as_mut().expect("piped");
            stdin
                .write_all(&image.rgba)
                .context("ffmpeg stopped taking frames (its error is above)")
        }

        /// Close ffmpeg's input and wait for it; the video's path.
        pub fn finish(mut self) -> anyhow::Result<PathBuf> {
            drop(self.child.stdin.take());
            let status = self.child.wait().context("waiting for ffmpeg")?;
            anyhow::ensure!(
                status.success(),
                "ffmpeg failed ({status}) writing {}: its error is above",
                self.path.display()
            );
            Ok(self.path)
        }
    }
}

/// `meshfree view DIR`: the window on the run's frames, one frame on per drawn frame
/// while playing (space pauses, `.` and `,` step one frame on and back, `<` and `>` go to
/// the first and the last, the slider to any: `Recorded::timeline`).
pub fn view_run(a: ViewArgs) -> anyhow::Result<()> {
    let mut rec = Recorded::open(Path::new(&a.scene))?;
    rec.go(0)?;
    let mut probe = FrameData::default();
    rec.fill(a.field, &mut probe)?;
    let dim = rec.run.scene.file.dimension;
    let opts = ViewOptions {
        title: format!(
            "meshfree: {} ({}, {} frames)",
            rec.run.scene.name(),
            rec.run.dir.display(),
            rec.run.frames.len()
        ),
        field: field(a.field),
        steps_per_frame: 1,
        hide_boundary: dim == 3,
        surface: a.surface,
        screenshot_dir: rec.run.dir.clone(),
        screenshot_after_frames: a.capture(),
        ..Default::default()
    };
    meshfree_viewer::run_window(&mut rec, opts).map_err(window_error)?;
    Ok(())
}
