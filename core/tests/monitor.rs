//! Force monitors (`src/measure/monitor.rs`): the Strouhal estimator on synthetic signals, the
//! end-of-run statistics, the wall force against the CPU force stage, and on a resting tank
//! (the fluid's weight).

mod common;

use meshfree_core::backend::cpu::CpuSolver;
use meshfree_core::backend::cpu_solver;
use meshfree_core::measure::monitor::{
    band_rms, dominant_frequency, wall_force, BluffBody, Coefficients, ForceSample, MonitorSummary,
};
use meshfree_core::physics::dim::{Dim, D2};
use meshfree_core::physics::particle::Kind;
use meshfree_core::scene::Scene;
use meshfree_core::solver::step::Stepper;
use meshfree_core::solver::Readback;
use meshfree_core::solver::Solver;

/// Uniform noise in [-0.5, 0.5) from a xorshift generator seeded with `seed`.
fn noise(mut seed: u64) -> impl FnMut() -> f64 {
    move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    }
}

/// A sine of frequency 1.37 with an offset, noise and a drag-like second harmonic, sampled
/// at jittered times over 9 periods: the DFT peak is the sine's frequency within 1 %.
#[test]
fn dominant_frequency_of_a_noisy_sine() {
    let f0 = 1.37;
    let mut rnd = noise(12345);
    let (mut t, mut x) = (Vec::new(), Vec::new());
    let mut tk = 3.0;
    while tk < 3.0 + 9.0 / f0 {
        t.push(tk);
        let w = 2.0 * std::f64::consts::PI * f0 * tk;
        x.push(0.4 + 0.3 * (w + 0.7).sin() + 0.1 * (2.0 * w).sin() + 0.1 * rnd());
        tk += 0.02 * (1.0 + 0.3 * rnd());
    }
    let f = dominant_frequency(&t, &x).expect("a frequency");
    assert!((f - f0).abs() < 0.01 * f0, "found {f}, expected {f0}");
    // Too short or constant signals give none.
    assert_eq!(dominant_frequency(&t[..5], &x[..5]), None);
    assert_eq!(dominant_frequency(&t, &vec![2.0; t.len()]), None);
}

/// A sine of amplitude 0.3 at 0.09 (a shedding lift at St 0.18, D / U = 2) with an offset, a
/// third harmonic and white noise of rms 0.2 (the SPH force noise at D / dx = 20), sampled
/// every 0.25 over 120 (`validate`'s cylinder window): the band's rms is the sine's
/// 0.3 / sqrt 2 within 8 %, where the record's rms (0.29) is 37 % high. The band holds
/// 4.5 % of the noise's variance (rms 0.04 here) and its cross term with the sine, a few
/// per cent of the result either way. A pure sine's off-bin frequency loses under 3 %.
#[test]
fn band_rms_of_a_noisy_sine() {
    let (f0, a) = (0.09, 0.3);
    let mut rnd = noise(987654321);
    let t: Vec<f64> = (0..480).map(|k| 0.25 * k as f64).collect();
    let w = |t: f64| 2.0 * std::f64::consts::PI * f0 * t;
    // Uniform noise on [-0.5, 0.5] has rms 1 / sqrt 12: times 0.2 sqrt 12, rms 0.2.
    let x: Vec<f64> = t
        .iter()
        .map(|&t| 0.1 + a * w(t).sin() + 0.01 * (3.0 * w(t)).sin() + 0.2 * 12f64.sqrt() * rnd())
        .collect();
    let want = a / 2f64.sqrt();
    let got = band_rms(&t, &x, f0, 0.5);
    assert!(
        (got / want - 1.0).abs() < 0.08,
        "band rms {got}, expected {want}"
    );
    let pure: Vec<f64> = t.iter().map(|&t| a * (w(t) + 0.4).sin()).collect();
    let got = band_rms(&t, &pure, f0, 0.5);
    assert!(
        (got / want - 1.0).abs() < 0.03,
        "band rms {got}, expected {want}"
    );
    // Little in a band that holds no signal (the record's edges leak an off-bin sine by
    // ~1 / (pi dk) of its amplitude into the bin dk away: 1 % at 4 f0); nothing from too
    // short a record.
    assert!(band_rms(&t, &pure, 4.0 * f0, 0.2) < 0.05 * want);
    assert_eq!(band_rms(&t[..1], &x[..1], f0, 0.5), 0.0);
}

/// The statistics over the second half of the record: St = f D / U, mean Cd, rms Cl.
#[test]
fn monitor_summary_of_a_synthetic_record() {
    let (u, d, f0) = (15.0, 2.0, 1.35);
    let samples: Vec<ForceSample> = (0..1000)
        .map(|k| {
            let t = k as f64 * 0.02;
            // Transient in the first half (ignored): a larger drag, no lift.
            let (cd, cl) = if t < 10.0 {
                (3.0, 0.0)
            } else {
                (1.4, 0.5 * (2.0 * std::f64::consts::PI * f0 * t).sin())
            };
            ForceSample {
                t,
                force: [cd, cl, 0.0],
                cd,
                cl,
            }
        })
        .collect();
    let body = BluffBody {
        velocity: u,
        length: d,
        blockage_ratio: 0.25,
    };
    let summary = MonitorSummary::of("forces", 0, &samples, Some(body));
    let s = summary.coefficients.clone().unwrap();
    let st = s.strouhal.expect("a Strouhal number");
    assert!((st - f0 * d / u).abs() < 0.005 * st, "St {st}");
    assert!((s.window_start - 9.99).abs() < 1e-9);
    assert!((s.mean_cd - 1.4).abs() < 1e-9, "mean Cd {}", s.mean_cd);
    assert!(
        (s.rms_cl - 0.5 / 2f64.sqrt()).abs() < 0.01,
        "rms Cl {}",
        s.rms_cl
    );
    assert_eq!(summary.samples, 1000);
    assert_eq!(s.blockage_ratio, 0.25);
    let line = summary.to_string();
    assert!(
        line.contains("Strouhal 0.18") && line.contains("blockage D/H 0.250"),
        "{line}"
    );
}

/// The end-of-run rms lift is the shedding's (issue #23): a lift of amplitude 0.3 at f0 with
/// white noise of rms 0.2 (the SPH force noise of a wake at D / dx = 20), sampled every
/// 0.02 as the built-in vortex streets' monitors: `rms_cl` is the band rms about the
/// dominant frequency, 0.3 / sqrt 2 within 8 %, where the record's rms (0.29) is 37 % high.
/// A constant lift gives 0.
#[test]
fn monitor_summary_rms_lift_leaves_the_noise_out() {
    let (u, d, f0, a) = (15.0, 2.0, 1.3, 0.3);
    let mut rnd = noise(24681357);
    let samples: Vec<ForceSample> = (0..1000)
        .map(|k| {
            let t = k as f64 * 0.02;
            let cl = a * (2.0 * std::f64::consts::PI * f0 * t).sin() + 0.2 * 12f64.sqrt() * rnd();
            ForceSample {
                t,
                force: [1.4, cl, 0.0],
                cd: 1.4,
                cl,
            }
        })
        .collect();
    let body = BluffBody {
        velocity: u,
        length: d,
        blockage_ratio: 0.25,
    };
    let s = Coefficients::of(&samples, body);
    let st = s.strouhal.expect("a Strouhal number");
    assert!((st - f0 * d / u).abs() < 0.01 * st, "St {st}");
    let want = a / 2f64.sqrt();
    assert!((s.rms_cl / want - 1.0).abs() < 0.08, "rms Cl {}", s.rms_cl);
    let flat: Vec<ForceSample> = samples
        .iter()
        .map(|x| ForceSample { cl: 0.1, ..*x })
        .collect();
    let s = Coefficients::of(&flat, body);
    assert!(s.rms_cl < 1e-12, "rms Cl {}", s.rms_cl);
}

/// A resting tank: the fluid's weight rests on the container, so the time-averaged force
/// of the fluid on the wall object is M g (down) within 2 %, and nothing sideways.
#[test]
fn resting_tank_wall_carries_the_fluid_weight() {
    let scene = Scene::builtin("tank-2d")
        .unwrap()
        .with_spacing(0.05)
        .unwrap();
    let setup = scene.setup().unwrap();
    let p = setup.params;
    let mass: f64 = setup
        .particles
        .iter()
        .filter(|q| q.kind == Kind::Fluid)
        .map(|q| q.mass as f64)
        .sum();
    let weight = mass * p.gravity[1] as f64; // negative: down
    let group = scene.wall_group(0);
    let mut s = cpu_solver(setup);
    let mut stepper = Stepper::default();
    stepper.advance_to(s.as_mut(), 0.3).unwrap();
    // Averaged over 0.5: the force rings by +-15 % with a period of about 0.1.
    let n = 50;
    let mut mean = [0.0f64; 3];
    for k in 1..=n {
        stepper
            .advance_to(s.as_mut(), 0.3 + 0.5 * k as f64 / n as f64)
            .unwrap();
        let f = wall_force(&p, &s.particles(), s.wall_surface(), group);
        for a in 0..3 {
            mean[a] += f[a] / n as f64;
        }
    }
    eprintln!("mean wall force {mean:?}, weight {weight}");
    assert!(
        (mean[1] - weight).abs() < 0.02 * weight.abs(),
        "vertical force {} vs the weight {weight}",
        mean[1]
    );
    assert!(
        mean[0].abs() < 0.01 * weight.abs(),
        "sideways force {}",
        mean[0]
    );
}

/// Runs `scene` 200 steps on the CPU, recomputes the forces, and checks that the monitor's
/// force on wall 0 is - sum_i m_i (a_i - g) over every particle that is no wall, within
/// 1e-4 of the vertical force; returns the solver for further checks.
fn check_monitor_against_force_stage(scene: &Scene) -> CpuSolver<D2> {
    let setup = scene.setup().unwrap();
    let p = setup.params;
    let mut c = CpuSolver::<D2>::new(setup);
    for _ in 0..200 {
        c.step();
    }
    c.build_grid();
    c.density();
    c.forces();
    let s = c.state();
    let g = D2::from3(p.gravity);
    let mut expect = [0.0f64; 2];
    for i in 0..s.len() {
        if s.kind[i] != Kind::Boundary.code() {
            let a = D2::to3(s.acc[i] - g);
            for k in 0..2 {
                expect[k] -= s.mass[i] as f64 * a[k] as f64;
            }
        }
    }
    let f = wall_force(&p, &c.particles(), c.wall_surface(), scene.wall_group(0));
    let scale = expect[1].abs();
    eprintln!("monitor {f:?}, force stage {expect:?}");
    for k in 0..2 {
        assert!(
            (f[k] - expect[k]).abs() < 1e-4 * scale,
            "axis {k}: monitor {} vs force stage {}",
            f[k],
            expect[k]
        );
    }
    c
}

/// The monitor's force is exactly the wall part of the force stage: fluid-fluid pair terms
/// cancel in sum m_i a_i, so - sum_i m_i (a_i - g) over the fluid is the force on the walls
/// (tank-2d after 200 steps, with laminar viscosity switched on as well).
#[test]
fn wall_force_is_the_wall_part_of_the_force_stage() {
    let mut scene = Scene::builtin("tank-2d")
        .unwrap()
        .with_spacing(0.05)
        .unwrap();
    scene.file.fluid.viscosity = 0.01;
    scene.revalidate().unwrap();
    check_monitor_against_force_stage(&scene);
}

/// The same with the no-slip walls of Morris et al. 1997 (`[boundary] no_slip = "morris"`):
/// the monitor takes the wall particles' extrapolated velocity as the force stage does.
#[test]
fn wall_force_is_the_wall_part_of_the_force_stage_with_no_slip_walls() {
    let scene = common::tank_2d_morris(0.05);
    check_monitor_against_force_stage(&scene);
}

/// The same identity with an elastic block standing on the monitored floor: a body meets a
/// wall through its pressure only (`[solid] interface = "pressure"`, `whole_stress_pair`),
/// in the force stage and in the monitor alike; body-body and body-fluid pair terms cancel
/// in sum m_i a_i as fluid-fluid ones do.
#[test]
fn wall_force_with_a_body_on_the_wall_is_the_wall_part_of_the_force_stage() {
    let scene = block_on_floor();
    let c = check_monitor_against_force_stage(&scene);
    assert!(
        c.state().solid.as_ref().is_some_and(|so| so
            .stress
            .iter()
            .any(|m| !m.abs_diff_eq(Default::default(), 1.0))),
        "the block carries a deviatoric stress after 200 steps"
    );
}

/// A tank of water beside an elastic block, both on the monitored floor (dynamic walls).
fn block_on_floor() -> Scene {
    let text = r#"dimension = 2
name = "block-on-floor"
gravity = [0.0, -9.81]

[domain]
min = [-0.2, -0.2]
max = [1.2, 1.3]

[discretisation]
spacing = 0.05

[time]
end = 1.0
output_interval = 0.1

[fluid]
density = 1000.0
sound_speed = 45.0
alpha = 0.02

[solid]
density = 1200.0
sound_speed = 60.0
shear_modulus = 2.0e5

[boundary]
strength = 1962.0
wall_coupling = "dynamic"

[[fluid_blocks]]
min = [0.0, 0.0]
max = [0.5, 0.5]
hydrostatic = true

[[solids]]
shape = "box"
min = [0.6, 0.0]
max = [0.9, 0.3]

[[walls]]
shape = "box-container"
min = [0.0, 0.0]
max = [1.0, 1.2]
layers = 3
"#;
    Scene::from_toml(text, "tests/monitor.rs").unwrap()
}

/// The CPU backend's own `wall_forces` (on its state: the grid rebuilt from the current
/// positions, the pressures of the current densities) against the read-back path
/// (`wall_force` on `particles()`), at t = 0 (unsorted storage, no grid yet) and between
/// steps, for the wall object and a group with no particles (zero); then the sampled run
/// against an unsampled twin. Both sums visit the same pairs in the same order (the
/// read-back's state is a subset of the same particles, sorted by the same (cell, id) key),
/// so they agree bit for bit (to 1e-5 with solids, whose density the read-back sees rounded:
/// `SolidState::rho_dev`), and so do the two runs.
fn check_direct_against_read_back(what: &str, scene: &Scene) {
    let setup = scene.setup().unwrap();
    let p = setup.params;
    let groups = [scene.wall_group(0), u32::MAX];
    let solids = setup.particles.iter().any(|q| q.kind == Kind::Solid);
    let (mut a, mut twin) = (cpu_solver(setup.clone()), cpu_solver(setup));
    for round in 0..4 {
        if round > 0 {
            for _ in 0..25 {
                a.step();
                twin.step();
            }
        }
        let parts = a.particles();
        let want: Vec<[f64; 3]> = groups
            .iter()
            .map(|&g| wall_force(&p, &parts, a.wall_surface(), g))
            .collect();
        let got = a.wall_forces(&groups);
        eprintln!("{what}, t = {:.4}: {got:?}", a.time());
        if solids {
            // The solver takes a solid's pressure from its density departure rho_dev, the
            // read-back from the composite density rho0_s + rho_dev rounded to f32: they
            // differ in rho's last bits (c_s^2 ulp(rho) per particle), not in the pairs.
            let scale = want[0].iter().fold(0.0f64, |m, f| m.max(f.abs()));
            for (g, w) in got.iter().zip(&want) {
                for k in 0..3 {
                    assert!(
                        (g[k] - w[k]).abs() <= 1e-5 * scale,
                        "{what}, t = {}: direct {g:?} vs read-back {w:?}",
                        a.time()
                    );
                }
            }
        } else {
            assert_eq!(got, want, "{what}, t = {}: direct vs read-back", a.time());
        }
        assert!(got[0].iter().any(|f| *f != 0.0), "{what}: no force");
        assert_eq!(got[1], [0.0; 3]);
    }
    for _ in 0..10 {
        a.step();
        twin.step();
    }
    assert_eq!(
        a.particles(),
        twin.particles(),
        "{what}: sampling changed the run"
    );
}

#[test]
fn cpu_wall_forces_equal_the_read_back_path() {
    let mut tank = Scene::builtin("tank-2d")
        .unwrap()
        .with_spacing(0.05)
        .unwrap();
    tank.file.fluid.viscosity = 0.01;
    tank.revalidate().unwrap();
    check_direct_against_read_back("tank-2d with laminar viscosity", &tank);
    check_direct_against_read_back(
        "tank-2d, Morris no-slip walls",
        &common::tank_2d_morris(0.05),
    );
    check_direct_against_read_back("block on the floor", &block_on_floor());
}

/// A monitor without a bluff body's scales (a dam-break obstacle) reports the peak force,
/// its time and the impulse, and no coefficient (issue #51).
#[test]
fn a_force_record_without_scales_gives_peak_and_impulse() {
    // A surge on an obstacle: F(t) = (100 t, -20 t, 0) up to t = 1, then 0 (half-sine free).
    let samples: Vec<ForceSample> = (0..=200)
        .map(|k| {
            let t = k as f64 * 0.01;
            let f = if t <= 1.0 { t } else { 0.0 };
            ForceSample {
                t,
                force: [100.0 * f, -20.0 * f, 0.0],
                cd: 0.0,
                cl: 0.0,
            }
        })
        .collect();
    let s = MonitorSummary::of("obstacle", 2, &samples, None);
    assert!(s.coefficients.is_none());
    assert!((s.peak_force - (100f64.powi(2) + 20f64.powi(2)).sqrt()).abs() < 1e-9);
    assert!((s.peak_time - 1.0).abs() < 1e-12);
    // The triangle's area 50 (x) and -10 (y), less the trapezoid's sliver past t = 1.
    assert!((s.impulse[0] - 50.5).abs() < 1e-9, "{:?}", s.impulse);
    assert!((s.impulse[1] + 10.1).abs() < 1e-9, "{:?}", s.impulse);
    let line = s.to_string();
    assert!(
        line.contains("peak |F|") && !line.contains("Strouhal"),
        "{line}"
    );
}
