//! `meshfree scenes` (the built-in scenes' counts, or the scene reference) and `meshfree
//! check` (validate a scene and count its particles).

use serde::Serialize;

use meshfree_core::scene::{self, Counts, Scene};

#[derive(Debug, clap::Args)]
pub struct ScenesArgs {
    /// Print JSON (an array of objects) instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Print the scene reference instead (Markdown: every key with its type, default and
    /// the reason for it, its value under --paper-exact, its check and the parameter
    /// field it sets), as committed in docs/reference/scene.md.
    #[arg(long, conflicts_with = "json")]
    pub reference: bool,
}

#[derive(Debug, clap::Args)]
pub struct CheckArgs {
    /// A scene file path or a built-in scene name.
    pub scene: String,
}

/// One row of `meshfree scenes`.
#[derive(Debug, Serialize)]
pub struct SceneRow {
    pub name: String,
    pub dimension: u32,
    pub description: String,
    #[serde(flatten)]
    pub counts: Counts,
}

/// Every built-in scene, generated.
pub fn scene_rows() -> anyhow::Result<Vec<SceneRow>> {
    scene::builtin_names()
        .into_iter()
        .map(|name| {
            let s = Scene::builtin(name)?;
            let setup = s.setup()?;
            Ok(SceneRow {
                name: name.to_string(),
                dimension: s.file.dimension,
                description: s.file.description.clone(),
                counts: Counts::of(&setup.particles),
            })
        })
        .collect()
}

/// `meshfree check` counts the particles exactly (by generating them) up to this estimate,
/// and prints the estimate above it, so that it answers within a second for any scene.
const CHECK_GENERATES_UP_TO: f64 = 2e6;

pub(super) fn scenes(a: ScenesArgs) -> anyhow::Result<()> {
    if a.reference {
        crate::out!("{}", meshfree_core::scene::scheme::reference::markdown())?;
        return Ok(());
    }
    let rows = scene_rows()?;
    if a.json {
        crate::outln!("{}", serde_json::to_string_pretty(&rows)?)?;
    } else {
        // The name column as wide as the longest name (vortex-street-re105 is 19).
        let w = rows.iter().map(|r| r.name.len()).max().unwrap_or(4).max(4);
        crate::outln!(
            "{:<w$} {:>3} {:>8} {:>8} {:>9} {:>8}  description",
            "name",
            "dim",
            "fluid",
            "solid",
            "boundary",
            "total"
        )?;
        for r in rows {
            crate::outln!(
                "{:<w$} {:>3} {:>8} {:>8} {:>9} {:>8}  {}",
                r.name,
                r.dimension,
                r.counts.fluid,
                r.counts.solid,
                r.counts.boundary,
                r.counts.total,
                r.description
            )?;
        }
    }
    Ok(())
}

pub(super) fn check(a: CheckArgs) -> anyhow::Result<()> {
    let s = Scene::load(&a.scene)?;
    let e = s.check_size(None)?;
    let p = s.params();
    if e.particles > CHECK_GENERATES_UP_TO {
        // Generating would take minutes and gigabytes: the estimate says enough.
        crate::outln!(
            "{}: ok: {} ({}D), up to {:.3e} particles (estimated, about {:.1} GB to \
             start); h = {}, {} neighbour cells",
            s.origin(),
            s.name(),
            s.file.dimension,
            e.particles,
            e.host_bytes() / 1e9,
            p.h,
            p.n_cells
        )?;
        return Ok(());
    }
    let setup = s.setup()?;
    let c = Counts::of(&setup.particles);
    crate::outln!(
        "{}: ok: {} ({}D), {} particles: {} fluid, {} solid, {} boundary; h = {}, {} neighbour cells",
        s.origin(),
        s.name(),
        s.file.dimension,
        c.total,
        c.fluid,
        c.solid,
        c.boundary,
        setup.params.h,
        setup.params.n_cells
    )?;
    for line in surface_lines(&s, &setup.particles) {
        crate::outln!("  {line}")?;
    }
    for line in body_lines(&s, &setup) {
        crate::outln!("  {line}")?;
    }
    for line in open_lines(&setup) {
        crate::outln!("  {line}")?;
    }
    Ok(())
}

/// One line per open boundary: its kind, plane, depth and buffer particles; for an inlet,
/// the particles and mass a second it lets in at full velocity (its buffer's particles times
/// the velocity along the normal over the depth).
fn open_lines(setup: &meshfree_core::solver::Setup) -> Vec<String> {
    let p = &setup.params;
    let axis = ["x", "y", "z"];
    p.open[..p.open_count.max(0) as usize]
        .iter()
        .enumerate()
        .map(|(b, o)| {
            let (n, mass) = (setup.particles.iter())
                .filter(|q| q.group as i32 == o.group)
                .fold((0usize, 0.0f64), |(n, m), q| (n + 1, m + q.mass as f64));
            let a = o.axis as usize;
            let sign = if o.sign > 0.0 { "+" } else { "-" };
            let head = format!(
                "open_boundaries[{b}]: {} at {} = {}, normal {sign}{}, {} deep",
                if o.is_inlet() { "inlet" } else { "outlet" },
                axis[a],
                o.plane,
                axis[a],
                o.depth
            );
            if o.is_inlet() {
                let rate = (o.sign * o.velocity[a]) as f64 / o.depth as f64;
                format!(
                    "{head}, {n} buffer particles: about {:.0} particles and {:.6} mass a \
                     second in at full velocity",
                    n as f64 * rate,
                    mass * rate
                )
            } else {
                format!("{head}: removes what flows out")
            }
        })
        .collect()
}

/// One line per floating body: its wall, mass, centre of mass, the principal moments of its
/// inertia tensor's diagonal, its free axes and the particles it has.
fn body_lines(s: &Scene, setup: &meshfree_core::solver::Setup) -> Vec<String> {
    let dim = s.file.dimension as usize;
    let base = s.wall_group(0) as i32;
    setup
        .bodies
        .iter()
        .map(|b| {
            let made = (setup.particles.iter())
                .filter(|p| p.group as i32 == b.group)
                .count();
            let c: Vec<String> = b.centre[..dim].iter().map(|x| format!("{x:.6}")).collect();
            let inertia = if dim == 2 {
                format!("{:.6e}", b.inertia[8])
            } else {
                format!(
                    "[{:.6e}, {:.6e}, {:.6e}]",
                    b.inertia[0], b.inertia[4], b.inertia[8]
                )
            };
            let axes = |from: i32| -> String {
                let a: Vec<&str> = (0..3)
                    .filter(|k| b.free & (1 << (from + k)) != 0)
                    .map(|k| ["x", "y", "z"][k as usize])
                    .collect();
                if a.is_empty() {
                    "none".into()
                } else {
                    a.join(", ")
                }
            };
            format!(
                "walls[{}].floating: mass {:.6}, centre of mass [{}], inertia {inertia}, moves \
                 along {}, turns about {}; {made} particles",
                b.group - base,
                b.mass,
                c.join(", "),
                axes(0),
                axes(3)
            )
        })
        .collect()
}

/// One line per surface of `s` (`mesh`, `polygon`, `inside`): its file, triangles (edges),
/// box, volume (area; an open one's own area or length), holes and orientation, and the
/// particles its object made.
fn surface_lines(
    s: &Scene,
    particles: &[meshfree_core::physics::particle::Particle],
) -> Vec<String> {
    let dim = s.file.dimension as usize;
    let v = |p: &[f64; 3]| {
        let xs: Vec<String> = p[..dim].iter().map(|x| format!("{x:.6}")).collect();
        format!("[{}]", xs.join(", "))
    };
    meshfree_core::scene::geometry::surfaces(&s.file)
        .into_iter()
        .filter_map(|placed| {
            let i = &placed.outline.loaded.get()?.info;
            let made = particles.iter().filter(|p| p.group == placed.group).count();
            let (elements, measure, size) = match (dim, i.open) {
                (3, false) => ("triangles", "volume", i.volume),
                (_, false) => ("edges", "area", i.volume),
                (3, true) => ("triangles", "area", i.area),
                (_, true) => ("edges", "length", i.area),
            };
            let t = &i.topology;
            let edges = if i.open {
                "open: its sides from its faces' order".to_string()
            } else if t.open_edges == 0 {
                "closed".to_string()
            } else {
                format!(
                    "{} open edges in {} hole(s), the largest {:.6} across (bridged)",
                    t.open_edges, t.holes, t.largest_hole
                )
            };
            let turned = if i.turned {
                "; wound inward, turned outward"
            } else {
                ""
            };
            Some(format!(
                "{}: {}: {} {elements}, box {} to {}, {measure} {:.6}, {edges}{turned}; {made} particles",
                placed.field,
                i.source,
                i.elements,
                v(&i.lo),
                v(&i.hi),
                size
            ))
        })
        .collect()
}
