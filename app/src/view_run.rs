//! The viewer glue for a finished run (issue #51): `meshfree render DIR` draws the frames a
//! run wrote (`output::frames`) headless, and `meshfree view DIR` steps through them in the
//! window (`Recorded`, a `LiveSource` that serves recorded frames instead of a solver).
//! Nothing is simulated again.

use std::path::{Path, PathBuf};

use anyhow::Context;
use meshfree::bad_input::BadInput;
use meshfree::cli::{RenderArgs, ShownField, ViewArgs};
use meshfree::output::frames::{kinds, values};
use meshfree::output::RecordedRun;
use meshfree_core::frame;
use meshfree_viewer::{
    Field, FrameData, LiveSource, Outline, Panel, RenderOptions, Status, ViewOptions,
};

use crate::view::{field, wall_outlines, window_error};

/// The viewer's field as the command line names it.
fn shown_field(f: Field) -> ShownField {
    match f {
        Field::Speed => ShownField::Speed,
        Field::Pressure => ShownField::Pressure,
        Field::Density => ShownField::Density,
        Field::Kind => ShownField::Kind,
    }
}

/// A run's frames as the viewer draws them: the scene's dimension, domain, particle radius
/// and box walls (gates leave at their removal time), around each frame read.
struct Recorded {
    run: RecordedRun,
    outlines: Vec<(Outline, Option<f64>)>,
    /// The frame shown and its index.
    index: usize,
    frame: frame::FrameData,
    /// Fields asked for that the run did not write, said once each (the window draws
    /// them as zero).
    said: Vec<ShownField>,
}

impl Recorded {
    fn open(dir: &Path) -> anyhow::Result<Recorded> {
        let run = RecordedRun::open(dir)?;
        Ok(Recorded {
            outlines: wall_outlines(&run.scene),
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
    fn fill(&self, f: ShownField, out: &mut FrameData) -> Result<(), BadInput> {
        let p = self.run.scene.params();
        out.dim = p.dim as u8;
        out.domain_min = p.domain_min;
        out.domain_max = p.domain_max;
        if p.dim == 2 {
            out.domain_min[2] = 0.0;
            out.domain_max[2] = 0.0;
        }
        out.particle_radius = 0.5 * p.dx;
        let t = self.frame.time;
        out.outlines.clear();
        out.outlines.extend(
            self.outlines
                .iter()
                .filter(|(_, removed)| removed.is_none_or(|r| t < r))
                .map(|(o, _)| *o),
        );
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
        let f = shown_field(f);
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
/// one, the one nearest `--at T`, or `--frames N` evenly spaced over the run's frames.
pub fn render_run(a: RenderArgs) -> anyhow::Result<()> {
    refuse_scene_flags(&a)?;
    let mut rec = Recorded::open(Path::new(&a.scene))?;
    let n = rec.run.frames.len();
    let stem = a.out.with_extension("");
    let numbered = |k: usize| PathBuf::from(format!("{}_{k:04}.png", stem.display()));
    let shots: Vec<(usize, PathBuf)> = match (a.frames, a.at) {
        (Some(count), _) => {
            let picks = rec.run.evenly(count.max(1) as usize);
            if picks.len() > n {
                meshfree::errln!(
                    "{} frames asked, the run has {n}: some are drawn more than once",
                    picks.len()
                );
            }
            picks
                .into_iter()
                .enumerate()
                .map(|(i, k)| (k, numbered(i)))
                .collect()
        }
        (None, Some(t)) => vec![(rec.run.nearest(t), a.out.clone())],
        (None, None) => vec![(n - 1, a.out.clone())],
    };
    let f = a.field;
    // The first frame is read and checked before EGL is opened: a missing field or a bad
    // file is said at once, where EGL is missing too.
    let mut frame = FrameData::default();
    rec.go(shots[0].0)?;
    rec.fill(f, &mut frame)?;
    if let Some(parent) = a.out.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(parent)
            .with_context(|| format!("creating {}", parent.display()))?;
    }
    let started = std::time::Instant::now();
    let mut renderer = meshfree_viewer::HeadlessRenderer::new()?;
    meshfree::errln!(
        "{}: {n} frames in {}; headless OpenGL: {}",
        rec.run.scene.name(),
        rec.run.dir.display(),
        renderer.gl_renderer()
    );
    let dim = rec.run.scene.file.dimension;
    for (k, path) in &shots {
        rec.go(*k)?;
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
            }),
            ..Default::default()
        };
        let image = renderer.render(&frame, &opts)?;
        image
            .save_png(path)
            .with_context(|| format!("writing {}", path.display()))?;
        meshfree::outln!(
            "wrote {} (t = {:.4}, frame {} of the run: {})",
            path.display(),
            status.time,
            k,
            rec.run.frames[*k].path.display()
        )?;
    }
    meshfree::errln!(
        "{} images in {:.2} s",
        shots.len(),
        started.elapsed().as_secs_f64()
    );
    Ok(())
}

/// `meshfree view DIR`: the window on the run's frames, one frame on per drawn frame
/// while playing (space pauses, `.` steps one frame, `r` goes back to the first).
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
        ..Default::default()
    };
    meshfree_viewer::run_window(&mut rec, opts).map_err(window_error)?;
    Ok(())
}
