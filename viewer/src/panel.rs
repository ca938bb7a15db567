//! The on-screen panel: the viewer's controls as rows of text, each row naming its key and
//! doing its action when clicked. The live window keeps a [`Controls`] that its keys and
//! clicks change; the headless renderer draws the same rows from a [`Panel`] in
//! [`RenderOptions::panel`](crate::RenderOptions::panel).

use crate::{Field, RenderOptions, Seek, Status, Timeline};

/// What a key or a click on a panel row does.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Action {
    /// Pause or resume the solver.
    Pause,
    /// One solver step, or a recorded run's next frame (pauses).
    Step,
    /// A recorded run's previous frame (pauses).
    Back,
    /// A recorded run's first frame (pauses).
    First,
    /// A recorded run's last frame (pauses).
    Last,
    /// Double the solver steps per drawn frame.
    Faster,
    /// Halve the solver steps per drawn frame.
    Slower,
    /// Colour by the next field.
    NextField,
    /// Hold the colour range where it is, or go back to the automatic range.
    LockRange,
    /// Show or hide the wall (boundary) particles.
    Walls,
    /// Show or hide the outlines of the container and obstacles (3D).
    Outlines,
    /// Show or hide the elastic bodies (solid particles).
    Bodies,
    /// Screen-space fluid surface on or off (3D).
    Surface,
    /// Show or hide the rarer keys.
    Help,
    /// Go back to the initial state.
    Reset,
    /// Write a PNG of the window.
    Screenshot,
    /// Frame the scene again.
    ResetCamera,
    /// Close the window.
    Close,
}

impl Action {
    /// The action of a character key, as the window's keyboard and the docs' key table
    /// give it (space is `" "`).
    pub fn for_key(c: &str) -> Option<Action> {
        Some(match c {
            " " => Action::Pause,
            "." | "n" | "N" => Action::Step,
            "," => Action::Back,
            "<" => Action::First,
            ">" => Action::Last,
            "+" | "=" => Action::Faster,
            "-" | "_" => Action::Slower,
            "f" | "F" => Action::NextField,
            "l" | "L" => Action::LockRange,
            "b" | "B" => Action::Walls,
            "o" | "O" => Action::Outlines,
            "e" | "E" => Action::Bodies,
            "s" | "S" => Action::Surface,
            "h" | "H" | "?" => Action::Help,
            "r" | "R" => Action::Reset,
            "p" | "P" => Action::Screenshot,
            "c" | "C" => Action::ResetCamera,
            "q" | "Q" => Action::Close,
            _ => return None,
        })
    }
}

/// The panel's state beyond what [`RenderOptions`] already holds (field, range, hidden
/// kinds, outlines, surface): the solver's progress and pace.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Panel {
    /// Time, step and particle count.
    pub status: Status,
    /// Solver paused.
    pub paused: bool,
    /// Solver steps per drawn frame.
    pub steps_per_frame: u32,
    /// Solver steps per second of wall time (measured by the caller).
    pub steps_per_second: f64,
    /// Drawn frames per second of wall time (measured by the caller).
    pub frames_per_second: f64,
    /// List the rarer keys (reset, screenshot, camera, quit) too.
    pub show_help: bool,
    /// A recorded run's place among its frames (`meshfree view DIR`); `None`: a live solver.
    pub timeline: Option<Timeline>,
}

/// One line of the panel: its text and what a click on it does.
pub(crate) type Row = (String, Option<Action>);

fn shown(on: bool) -> &'static str {
    if on {
        "shown"
    } else {
        "hidden"
    }
}

/// The panel's lines for a frame of dimension `dim` coloured over `range`.
pub(crate) fn rows(p: &Panel, o: &RenderOptions, dim: u8, range: (f32, f32)) -> Vec<Row> {
    let st = &p.status;
    let running = (
        format!("space  {}", if p.paused { "PAUSED" } else { "running" }),
        Some(Action::Pause),
    );
    let mut r: Vec<Row> = match p.timeline {
        // A recorded run: frames, not solver steps.
        Some(tl) => vec![
            (
                format!("t {:.5}  frame {} of {}", st.time, tl.frame + 1, tl.frames),
                None,
            ),
            (format!("particles {}", st.particles), None),
            running,
            ("n      next frame".into(), Some(Action::Step)),
            (",      previous frame".into(), Some(Action::Back)),
            ("<      first frame".into(), Some(Action::First)),
            (">      last frame".into(), Some(Action::Last)),
            (
                format!("+      frames/frame {}", p.steps_per_frame),
                Some(Action::Faster),
            ),
            ("-      fewer frames/frame".into(), Some(Action::Slower)),
        ],
        None => vec![
            (format!("t {:.5}  step {}", st.time, st.step), None),
            (format!("particles {}", st.particles), None),
            (
                format!(
                    "steps/s {:.0}  frames/s {:.1}",
                    p.steps_per_second, p.frames_per_second
                ),
                None,
            ),
            running,
            ("n      one step".into(), Some(Action::Step)),
            (
                format!("+      steps/frame {}", p.steps_per_frame),
                Some(Action::Faster),
            ),
            ("-      fewer steps/frame".into(), Some(Action::Slower)),
        ],
    };
    r.push((
        format!("f      field {}", o.field.label()),
        Some(Action::NextField),
    ));
    let range_text = if o.field == Field::Kind {
        "0 .. 2".to_string()
    } else {
        format!(
            "{} .. {}",
            crate::colormap::fmt_value(range.0),
            crate::colormap::fmt_value(range.1)
        )
    };
    r.push((
        format!(
            "l      range {range_text} {}",
            if o.range.is_some() { "held" } else { "auto" }
        ),
        Some(Action::LockRange),
    ));
    r.push((
        format!("b      walls {}", shown(!o.hide_kinds[2])),
        Some(Action::Walls),
    ));
    r.push((
        format!("e      bodies {}", shown(!o.hide_kinds[1])),
        Some(Action::Bodies),
    ));
    if dim == 3 {
        r.push((
            format!("o      outlines {}", shown(o.outlines)),
            Some(Action::Outlines),
        ));
        r.push((
            format!("s      surface {}", if o.surface { "on" } else { "off" }),
            Some(Action::Surface),
        ));
    }
    if p.show_help {
        r.extend([
            ("r      reset".to_string(), Some(Action::Reset)),
            ("p      screenshot".to_string(), Some(Action::Screenshot)),
            (
                "c      frame the scene".to_string(),
                Some(Action::ResetCamera),
            ),
            ("q esc  quit".to_string(), Some(Action::Close)),
            ("mouse  drag, wheel zoom".to_string(), None),
            ("h      fewer keys".to_string(), Some(Action::Help)),
        ]);
    } else {
        r.push(("h      more keys".into(), Some(Action::Help)));
    }
    r
}

/// The state the live window's keys and panel clicks change.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Controls {
    pub field: Field,
    pub steps_per_frame: u32,
    pub paused: bool,
    pub single_step: bool,
    /// `hide_kinds[k]` hides particles of kind `k`.
    pub hide_kinds: [bool; 3],
    pub outlines: bool,
    pub surface: bool,
    /// A held colour range; `None`: automatic.
    pub range: Option<(f32, f32)>,
    pub show_help: bool,
}

/// What an action asks of the window beyond [`Controls`]' own state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Outcome {
    None,
    Close,
    Reset,
    Screenshot,
    ResetCamera,
    /// Show another frame of a recorded run.
    Seek(Seek),
}

impl Controls {
    /// Applies `a`; `range` is the colour range last drawn (what [`Action::LockRange`] holds).
    pub fn apply(&mut self, a: Action, range: (f32, f32)) -> Outcome {
        match a {
            Action::Pause => self.paused = !self.paused,
            Action::Step => {
                self.paused = true;
                self.single_step = true;
            }
            Action::Back | Action::First | Action::Last => {
                self.paused = true;
                return Outcome::Seek(match a {
                    Action::Back => Seek::Back,
                    Action::First => Seek::First,
                    _ => Seek::Last,
                });
            }
            Action::Faster => self.steps_per_frame = (self.steps_per_frame * 2).min(1 << 16),
            Action::Slower => self.steps_per_frame = (self.steps_per_frame / 2).max(1),
            Action::NextField => {
                self.field = self.field.next();
                self.range = None;
            }
            Action::LockRange => {
                self.range = match self.range {
                    Some(_) => None,
                    None => Some(range),
                }
            }
            Action::Walls => self.hide_kinds[2] = !self.hide_kinds[2],
            Action::Bodies => self.hide_kinds[1] = !self.hide_kinds[1],
            Action::Outlines => self.outlines = !self.outlines,
            Action::Surface => self.surface = !self.surface,
            Action::Help => self.show_help = !self.show_help,
            Action::Reset => return Outcome::Reset,
            Action::Screenshot => return Outcome::Screenshot,
            Action::ResetCamera => return Outcome::ResetCamera,
            Action::Close => return Outcome::Close,
        }
        Outcome::None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn controls() -> Controls {
        Controls {
            field: Field::Speed,
            steps_per_frame: 1,
            paused: false,
            single_step: false,
            hide_kinds: [false; 3],
            outlines: true,
            surface: false,
            range: None,
            show_help: false,
        }
    }

    #[test]
    fn actions_drive_the_controls() {
        let mut c = controls();
        let r = (0.0, 1.0);
        let key = |c: &mut Controls, k: &str| c.apply(Action::for_key(k).unwrap(), r);
        key(&mut c, " ");
        assert!(c.paused);
        key(&mut c, " ");
        assert!(!c.paused);
        key(&mut c, ".");
        assert!(c.paused && c.single_step);
        for _ in 0..3 {
            key(&mut c, "+");
        }
        assert_eq!(c.steps_per_frame, 8);
        key(&mut c, "-");
        assert_eq!(c.steps_per_frame, 4);
        for _ in 0..10 {
            key(&mut c, "-");
        }
        assert_eq!(c.steps_per_frame, 1);
        let fields: Vec<Field> = (0..4)
            .map(|_| {
                key(&mut c, "f");
                c.field
            })
            .collect();
        assert_eq!(
            fields,
            [Field::Pressure, Field::Density, Field::Kind, Field::Speed]
        );
        key(&mut c, "l");
        assert_eq!(c.range, Some(r));
        key(&mut c, "f");
        assert_eq!(c.range, None, "a new field starts with the automatic range");
        key(&mut c, "b");
        key(&mut c, "e");
        assert_eq!(c.hide_kinds, [false, true, true]);
        key(&mut c, "o");
        key(&mut c, "s");
        assert!(!c.outlines && c.surface);
        key(&mut c, "h");
        assert!(c.show_help);
        assert_eq!(key(&mut c, "r"), Outcome::Reset);
        assert_eq!(key(&mut c, "p"), Outcome::Screenshot);
        assert_eq!(key(&mut c, "c"), Outcome::ResetCamera);
        assert_eq!(key(&mut c, "q"), Outcome::Close);
        assert_eq!(Action::for_key("z"), None);
    }

    #[test]
    fn rows_show_the_state_and_name_their_actions() {
        let p = Panel {
            status: Status {
                time: 0.5,
                step: 42,
                particles: 1234,
            },
            paused: true,
            steps_per_frame: 10,
            steps_per_second: 2000.0,
            frames_per_second: 60.0,
            show_help: false,
            timeline: None,
        };
        let o = RenderOptions {
            surface: true,
            hide_kinds: [false, false, true],
            ..RenderOptions::default()
        };
        let text = |rows: &[Row]| rows.iter().map(|r| r.0.clone()).collect::<Vec<_>>();
        let r3 = rows(&p, &o, 3, (0.0, 2.5));
        let t = text(&r3).join("\n");
        for want in [
            "step 42",
            "particles 1234",
            "steps/s 2000",
            "frames/s 60.0",
            "PAUSED",
            "steps/frame 10",
            "field speed",
            "range 0 .. 2.500 auto",
            "walls hidden",
            "bodies shown",
            "outlines shown",
            "surface on",
        ] {
            assert!(t.contains(want), "{want:?} not in\n{t}");
        }
        // Every row with a key names an action that its key also does.
        for (line, action) in &r3 {
            if let Some(a) = action {
                let key = line.split_whitespace().next().unwrap();
                let key = if key == "space" { " " } else { key };
                assert_eq!(Action::for_key(key), Some(*a), "{line}");
            }
        }
        // 2D has no outlines or surface rows; help adds the rarer keys.
        let r2 = rows(
            &Panel {
                show_help: true,
                ..p
            },
            &o,
            2,
            (0.0, 1.0),
        );
        let t2 = text(&r2).join("\n");
        assert!(!t2.contains("surface") && !t2.contains("outlines"), "{t2}");
        assert!(t2.contains("screenshot") && t2.contains("quit"), "{t2}");
        assert!(
            !t2.contains("frame 1 of") && !t2.contains("previous frame"),
            "{t2}"
        );
    }

    #[test]
    fn a_recorded_run_has_frame_rows_and_keys_that_go_back() {
        let p = Panel {
            status: Status {
                time: 0.25,
                step: 4,
                particles: 10,
            },
            paused: true,
            steps_per_frame: 1,
            steps_per_second: 0.0,
            frames_per_second: 30.0,
            show_help: false,
            timeline: Some(Timeline {
                frame: 4,
                frames: 11,
                times: (0.0, 0.5),
            }),
        };
        let rows = rows(&p, &RenderOptions::default(), 2, (0.0, 1.0));
        let t: Vec<&str> = rows.iter().map(|r| r.0.as_str()).collect();
        let t = t.join("\n");
        for want in [
            "frame 5 of 11",
            "next frame",
            "previous frame",
            "first frame",
            "last frame",
        ] {
            assert!(t.contains(want), "{want:?} not in\n{t}");
        }
        assert!(
            !t.contains("steps/s"),
            "a recorded run takes no steps:\n{t}"
        );
        for (line, action) in &rows {
            if let Some(a) = action {
                let key = line.split_whitespace().next().unwrap();
                let key = if key == "space" { " " } else { key };
                assert_eq!(Action::for_key(key), Some(*a), "{line}");
            }
        }
        let mut c = controls();
        let r = (0.0, 1.0);
        assert_eq!(c.apply(Action::Back, r), Outcome::Seek(Seek::Back));
        assert!(c.paused, "a seek pauses the playback");
        assert_eq!(c.apply(Action::First, r), Outcome::Seek(Seek::First));
        assert_eq!(c.apply(Action::Last, r), Outcome::Seek(Seek::Last));
        let tl = p.timeline.unwrap();
        assert_eq!(tl.target(Seek::Back), 3);
        assert_eq!(tl.target(Seek::First), 0);
        assert_eq!(tl.target(Seek::Last), 10);
        assert_eq!(tl.target(Seek::Fraction(0.5)), 5);
        assert_eq!(tl.target(Seek::Fraction(1.7)), 10);
        assert_eq!(tl.target(Seek::Fraction(f64::NAN)), 0);
        let first = Timeline { frame: 0, ..tl };
        assert_eq!(
            first.target(Seek::Back),
            0,
            "the first frame has none before it"
        );
    }
}
