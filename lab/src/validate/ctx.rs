//! What a case gets to build and run its scenes: the `Tier` it runs at, the `Ctx` (backend,
//! Courant number and integrator overrides, where to write plots, and the `edit` that
//! perturbs every scene it builds), and `Sim`, a solver stepped to given times with the
//! stepper's health checks, which reports the `RunInfo` its `Check` rows carry.

use std::path::Path;
use std::time::Instant;

use serde::{Deserialize, Serialize};

use meshfree_core::backend::{self, BackendChoice};
use meshfree_core::scene::scheme::declare::ToParam;
use meshfree_core::scene::scheme::{Assignment, IntegratorChoice};
use meshfree_core::scene::{Counts, Scene};
use meshfree_core::solver::step::Stepper;
use meshfree_core::solver::{Setup, Solver};

use super::check::RunInfo;

/// Quick (coarse, robust, for the test suite) or full (three resolutions, literature).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Tier {
    Quick,
    Full,
}

/// What a case gets.
pub struct Ctx<'a> {
    pub tier: Tier,
    pub backend: BackendChoice,
    /// `Options::courant`.
    pub courant: Option<f64>,
    /// `Options::integrator`.
    pub integrator: Option<IntegratorChoice>,
    /// `Options::sets`: scheme keys set in every scene that has their table.
    pub sets: &'a [Assignment],
    /// Where the case writes its plots.
    pub out_dir: &'a Path,
    pub verbose: bool,
    /// Changes every scene the case builds, after the case's own changes, before it runs
    /// (the scene is revalidated): a perturbed scheme, to show that a check can fail
    /// (`tests/perturbed.rs`). None: the case as written (`run` sets none).
    pub edit: Option<&'a dyn Fn(&mut Scene)>,
}

impl Ctx<'_> {
    /// The case's scene from its TOML text `text` (named `origin` in errors), with `sets`
    /// and `edit` applied.
    pub fn scene(&self, text: &str, origin: &str) -> anyhow::Result<Scene> {
        let mut scene = Scene::from_toml(text, origin)?;
        self.perturb(&mut scene)?;
        Ok(scene)
    }

    /// Apply `sets`, then `edit`, to a scene the case has finished changing, and
    /// revalidate it where either changed it.
    pub fn perturb(&self, scene: &mut Scene) -> anyhow::Result<()> {
        let mut changed = false;
        for a in self.sets {
            changed |= a
                .apply(&mut scene.file)
                .map_err(|e| anyhow::anyhow!("--set {a}: {e}"))?;
        }
        if let Some(edit) = self.edit {
            edit(scene);
            changed = true;
        }
        if changed {
            scene.revalidate()?;
        }
        Ok(())
    }

    pub fn log(&self, line: &str) {
        if self.verbose {
            crate::note!("  {line}");
        }
    }
}

/// A solver with the scene's gates, stepped to given times with health checks.
pub struct Sim {
    pub solver: Box<dyn Solver>,
    stepper: Stepper,
    pub counts: Counts,
    started: Instant,
    resolution: String,
}

impl Sim {
    pub fn new(
        ctx: &Ctx,
        setup: Setup,
        gates: Vec<(u32, f64)>,
        resolution: String,
    ) -> anyhow::Result<Sim> {
        let counts = Counts::of(&setup.particles);
        let mut setup = setup;
        // Another integrator runs at its own default Courant number unless one is given.
        if let Some(i) = ctx.integrator {
            setup.params.integrator = i.to_param();
            setup.params.courant = i.default_courant() as f32;
        }
        if let Some(c) = ctx.courant {
            setup.params.courant = c as f32;
        }
        let solver = backend::create(ctx.backend, backend::Layout::One, setup)?;
        Ok(Sim {
            solver,
            stepper: Stepper::new(gates),
            counts,
            started: Instant::now(),
            resolution,
        })
    }

    /// Step until the clock reaches `t` (the last step may pass it by less than one dt),
    /// removing gates whose time came; a blow-up is an error.
    pub fn advance_to(&mut self, t: f64) -> anyhow::Result<()> {
        self.stepper.advance_to(self.solver.as_mut(), t)?;
        Ok(())
    }

    pub fn info(&self) -> RunInfo {
        RunInfo {
            resolution: self.resolution.clone(),
            particles: self.counts.total,
            wall_seconds: self.started.elapsed().as_secs_f64(),
            info: self.solver.info(),
        }
    }
}
