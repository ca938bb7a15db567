//! Domain decomposition on the GPU (`backend/cuda/subdomain.rs`, `cuda/exchange.cu`): N
//! CUDA subdomains on one GPU, their halos packed, unpacked and compacted on the device,
//! equal the one-domain CUDA run bit for bit in every particle's position, velocity,
//! density, pressure and stress, on the scenes of `tests/exchange.rs` (2D and 3D dam breaks,
//! the paper's scheme, elastic bodies with a gate, a periodic channel with inflow); the
//! wall forces to round-off and the probes exactly; a save restored into another cut; and
//! the decomposed GPU run against the decomposed CPU run within the parity tests' long-run
//! tolerances. One more test, ignored always, times a step of the 1M-particle 3D dam break
//! of `scenes/peers` in 1, 2 and 4 subdomains (`--ignored one_gpu_timing`).
//!
//! The tests that need a GPU are `#[ignore]`d unless the build had `MESHFREE_REQUIRE_CUDA=1`
//! (`build.rs` turns it into the cfg `meshfree_require_cuda`); `-- --include-ignored` runs
//! them too. A test that runs fails without a usable GPU: it never passes by skipping.
#![cfg(feature = "cuda")]

mod common;

use meshfree_core::backend::cuda::CudaSolver;
use meshfree_core::backend::{self, BackendChoice};
use meshfree_core::exchange::{balanced, longest_axis, Decomposed};
use meshfree_core::physics::dim::{D2, D3};
use meshfree_core::physics::particle::Particle;
use meshfree_core::scene::Scene;

use common::edited_scene as scene;
use meshfree_core::solver::{Setup, Solver};

fn need_gpu<T>(r: Result<T, backend::BackendError>) -> T {
    r.unwrap_or_else(|e| {
        panic!(
            "this GPU test needs a usable CUDA device: {e} (it ran because the build had \
             MESHFREE_REQUIRE_CUDA=1, or because of --ignored / --include-ignored)"
        )
    })
}

/// `setup` on `choice` in `n` subdomains (0: one domain, no decomposition), gates opened
/// first, stepped `steps` steps (the one domain through `advance`, which replays CUDA
/// graphs); the particles by id and the solver.
fn run(
    choice: BackendChoice,
    setup: &Setup,
    gates: &[u32],
    n: usize,
    steps: u64,
) -> (Vec<Particle>, Box<dyn Solver>) {
    let mut s = if n == 0 {
        need_gpu(backend::create(choice, backend::Layout::One, setup.clone()))
    } else {
        need_gpu(backend::create(
            choice,
            backend::Layout::Threads(n),
            setup.clone(),
        ))
    };
    for &g in gates {
        s.remove_group(g);
    }
    s.advance(steps);
    (s.particles(), s)
}

/// Whether two particle sets (by id) hold the same bits; the first difference otherwise.
fn same(a: &[Particle], b: &[Particle]) -> Result<(), String> {
    if a.len() != b.len() {
        return Err(format!("{} particles against {}", a.len(), b.len()));
    }
    let bits = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    let mut first = None;
    let mut count = 0;
    for (p, q) in a.iter().zip(b) {
        if p.id != q.id {
            return Err(format!("particle {} against {}", p.id, q.id));
        }
        let fields: [(&str, Vec<u32>, Vec<u32>); 5] = [
            ("position", bits(&p.position), bits(&q.position)),
            ("velocity", bits(&p.velocity), bits(&q.velocity)),
            ("density", bits(&[p.density]), bits(&[q.density])),
            ("pressure", bits(&[p.pressure]), bits(&[q.pressure])),
            ("stress", bits(&p.stress), bits(&q.stress)),
        ];
        if let Some((what, _, _)) = fields.iter().find(|f| f.1 != f.2) {
            count += 1;
            first.get_or_insert_with(|| {
                format!(
                    "particle {} ({:?}) differs in {what}: {p:?}\nagainst {q:?}",
                    p.id, p.kind
                )
            });
        }
    }
    match first {
        None => Ok(()),
        Some(f) => Err(format!("{count} of {} particles differ; {f}", a.len())),
    }
}

/// The one-domain CUDA run against 2 and 4 CUDA subdomains after `steps` steps: the same
/// bits, the same clock and step, and the particles moved.
fn decomposed_equals_one_domain(name: &str, setup: &Setup, gates: &[u32], steps: u64) {
    let (one, mut s1) = run(BackendChoice::Cuda, setup, gates, 0, steps);
    assert!(
        one.iter()
            .zip(&setup.particles)
            .any(|(a, b)| a.position != b.position),
        "{name}: nothing moved"
    );
    for n in [2, 4] {
        let (many, mut sn) = run(BackendChoice::Cuda, setup, gates, n, steps);
        eprintln!("{name}: {}", sn.info().device);
        same(&one, &many)
            .unwrap_or_else(|e| panic!("{name}, {n} CUDA subdomains, {steps} steps: {e}"));
        assert_eq!(sn.steps(), s1.steps());
        assert_eq!(
            sn.time().to_bits(),
            s1.time().to_bits(),
            "{name}: the clocks differ"
        );
        let (d1, dn) = (s1.diagnostics(), sn.diagnostics());
        assert_eq!(
            (d1.fluid, d1.solid, d1.boundary),
            (dn.fluid, dn.solid, dn.boundary)
        );
        assert_eq!(d1.dt.to_bits(), dn.dt.to_bits(), "{name}: dt");
        assert_eq!(d1.max_speed.to_bits(), dn.max_speed.to_bits());
        let rel = (d1.kinetic_energy - dn.kinetic_energy).abs() / d1.kinetic_energy.max(1e-300);
        assert!(
            rel < 1e-12,
            "{name}: kinetic energy {} against {}",
            d1.kinetic_energy,
            dn.kinetic_energy
        );
        assert!(sn.check().is_ok());
    }
}

fn dam_break_2d() -> Scene {
    scene("dam-break-2d", &[("spacing = 0.02", "spacing = 0.03")])
}

fn impinging_2d() -> Scene {
    scene(
        "impinging-2d",
        &[
            ("spacing = 0.375", "spacing = 0.75"),
            ("layers = 3", "layers = 2"),
        ],
    )
}

fn vortex_street() -> Scene {
    scene(
        "vortex-street-re105",
        &[("spacing = 0.06", "spacing = 0.15")],
    )
}

fn gates_of(sc: &Scene) -> Vec<u32> {
    sc.gates().iter().map(|g| g.0).collect()
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn a_2d_dam_break_in_cuda_subdomains_equals_one_domain() {
    let sc = dam_break_2d();
    decomposed_equals_one_domain("dam-break-2d", &sc.setup().unwrap(), &gates_of(&sc), 60);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn the_paper_scheme_in_cuda_subdomains_equals_one_domain() {
    // Summation density (one more neighbour pass in the halo) and the forward Euler (the
    // fused forces-and-rates kernel, the drift-kick).
    let sc = dam_break_2d().with_paper_exact().unwrap();
    decomposed_equals_one_domain(
        "dam-break-2d --paper-exact",
        &sc.setup().unwrap(),
        &gates_of(&sc),
        60,
    );
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn a_3d_dam_break_in_cuda_subdomains_equals_one_domain() {
    let sc = scene("dam-break-3d", &[("spacing = 0.04", "spacing = 0.05")]);
    decomposed_equals_one_domain("dam-break-3d", &sc.setup().unwrap(), &gates_of(&sc), 30);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn elastic_bodies_and_a_gate_in_cuda_subdomains_equal_one_domain() {
    // Solids: the stress planes and rho_dev travel in the halo; subdomains that start with
    // no solid hold the solid arrays all the same (own_solids).
    let sc = impinging_2d();
    let setup = sc.setup().unwrap();
    assert!(setup.has_solids());
    decomposed_equals_one_domain("impinging-2d", &setup, &gates_of(&sc), 60);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn a_periodic_channel_with_inflow_in_cuda_subdomains_equals_one_domain() {
    // Cut along x, the periodic axis: the first and last slabs are neighbours round it.
    let setup = vortex_street().setup().unwrap();
    assert_eq!(longest_axis(&setup.params), 0);
    assert!(setup.params.periodic[0] != 0 && setup.params.inflow != 0);
    decomposed_equals_one_domain("vortex-street-re105", &setup, &[], 40);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn wall_forces_probes_and_a_restore_work_across_cuda_subdomains() {
    let setup = vortex_street().setup().unwrap();
    let (_, mut one) = run(BackendChoice::Cuda, &setup, &[], 0, 20);
    let (_, mut many) = run(BackendChoice::Cuda, &setup, &[], 3, 20);
    // The cylinder is group 1; its force summed over the owned wall particles of each
    // subdomain (the owned mask of cuda/monitor.cu), in another order: equal to round-off.
    let (f1, f3) = (one.wall_forces(&[1]), many.wall_forces(&[1]));
    let scale = f1[0][0].abs().max(f1[0][1].abs());
    assert!(scale > 0.0);
    for a in 0..2 {
        assert!(
            (f1[0][a] - f3[0][a]).abs() <= 1e-9 * scale,
            "wall force {f1:?} against {f3:?}"
        );
    }
    // Probes on both sides of every cut see the same particles.
    let xs: Vec<f32> = setup.particles.iter().map(|q| q.position[0]).collect();
    let slabs = balanced(&setup.params, 0, &xs, 3);
    let points: Vec<[f32; 3]> = slabs[1..]
        .iter()
        .flat_map(|s| {
            [
                [s.lo - 0.05, 1.0, 0.0],
                [s.lo + 0.05, 1.0, 0.0],
                [s.lo, 4.5, 0.0],
            ]
        })
        .collect();
    let (mut p1, mut p3) = (Vec::new(), Vec::new());
    one.sample_points(&points, false, &mut p1);
    many.sample_points(&points, false, &mut p3);
    assert_eq!(p1, p3, "probe samples");
    assert!(p1.iter().all(|s| s.neighbours > 0));
    // Stepping on after the samples is unchanged, and a save restored into a fresh
    // decomposition (2 subdomains: another cut) steps on as the one domain does.
    one.advance(10);
    many.advance(10);
    same(&one.particles(), &many.particles()).unwrap();
    let saved = many.save();
    let mut two = need_gpu(backend::create(
        BackendChoice::Cuda,
        backend::Layout::Threads(2),
        setup.clone(),
    ));
    two.restore(&saved).unwrap();
    one.advance(10);
    two.advance(10);
    same(&one.particles(), &two.particles()).unwrap();
    assert_eq!(one.time().to_bits(), two.time().to_bits());
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn single_steps_of_one_cuda_domain_equal_its_graphs() {
    // The capacity beside the count leaves one domain as it was: stage by stage and through
    // captured graphs, the same bits.
    let sc = dam_break_2d();
    let setup = sc.setup().unwrap();
    let (graphs, _) = run(BackendChoice::Cuda, &setup, &gates_of(&sc), 0, 40);
    let mut s = need_gpu(backend::create(
        BackendChoice::Cuda,
        backend::Layout::One,
        setup.clone(),
    ));
    for g in gates_of(&sc) {
        s.remove_group(g);
    }
    for _ in 0..40 {
        s.step();
    }
    same(&graphs, &s.particles()).unwrap();
}

/// The decomposed GPU run against the decomposed CPU run (another cut, too), within the
/// tolerances of the parity tests' long runs (`long_run_on` in tests/cuda_parity/compare.rs).
fn cpu_and_gpu_decomposed_agree(name: &str, setup: &Setup, gates: &[u32], steps: u64) {
    let (_, mut c) = run(BackendChoice::Cpu, setup, gates, 3, steps);
    let (_, mut g) = run(BackendChoice::Cuda, setup, gates, 2, steps);
    let (dc, dg) = (c.diagnostics(), g.diagnostics());
    eprintln!("{name} after {steps} steps:\n  cpu x3 {dc:?}\n  gpu x2 {dg:?}");
    assert!(c.check().is_ok() && g.check().is_ok());
    common::assert_long_run_close(&dc, &dg);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn cpu_and_cuda_subdomains_agree() {
    let sc = dam_break_2d();
    cpu_and_gpu_decomposed_agree("dam-break-2d", &sc.setup().unwrap(), &gates_of(&sc), 100);
    let sc = impinging_2d();
    cpu_and_gpu_decomposed_agree("impinging-2d", &sc.setup().unwrap(), &gates_of(&sc), 60);
}

#[test]
#[cfg_attr(
    not(meshfree_require_cuda),
    ignore = "needs a CUDA GPU: build with MESHFREE_REQUIRE_CUDA=1, or run with --include-ignored"
)]
fn a_cuda_solver_opens_device_zero_by_ordinal() {
    let setup = dam_break_2d().setup().unwrap();
    let s = need_gpu(CudaSolver::<D2>::new_on(setup.clone(), 0));
    assert_eq!(s.len(), setup.particles.len());
    let e = CudaSolver::<D2>::new_on(setup, 1 << 20)
        .err()
        .expect("no such device");
    assert!(e.to_string().contains("no device"), "{e}");
}

/// ms per step of `s` over `steps` steps (after `warm` of them), stage by stage.
fn ms_per_step(s: &mut dyn Solver, warm: u64, steps: u64) -> f64 {
    for _ in 0..warm {
        s.step();
    }
    s.time();
    let t0 = std::time::Instant::now();
    for _ in 0..steps {
        s.step();
    }
    s.time(); // waits for the queued work
    t0.elapsed().as_secs_f64() * 1e3 / steps as f64
}

#[test]
#[ignore = "a timing (about 1M particles): run with --ignored one_gpu_timing"]
fn one_gpu_timing_of_a_1m_particle_3d_dam_break_in_subdomains() {
    let sc = Scene::from_toml(
        include_str!("../../scenes/peers/db3d-ppH70.toml"),
        "db3d-ppH70",
    )
    .unwrap();
    let mut setup = sc.setup().unwrap();
    let whole = setup.particles.len();
    eprintln!("db3d-ppH70: {whole} particles");
    let (warm, steps) = (3, 10);
    {
        let mut one = need_gpu(CudaSolver::<D3>::new(setup.clone()));
        eprintln!("device: {}", one.info().device);
        let t = ms_per_step(&mut one, warm, steps);
        let t0 = std::time::Instant::now();
        one.advance(steps);
        one.time();
        let tg = t0.elapsed().as_secs_f64() * 1e3 / steps as f64;
        eprintln!(
            "1 domain: {t:.2} ms/step stage by stage, {tg:.2} ms/step through graphs (lanes {})",
            one.lanes()
        );
    }
    setup.params.own_solids = setup.has_solids() as i32;
    for n in [2, 4] {
        let mut d = need_gpu(Decomposed::new(setup.clone(), n, |s| {
            CudaSolver::<D3>::new_subdomain(s, whole, 0)
        }));
        let t = ms_per_step(&mut d, warm, steps);
        let st = d.exchange_stats();
        let fills = st.iter().map(|x| x.fills).max().unwrap_or(0).max(1);
        let ex_ms: Vec<String> = st
            .iter()
            .map(|x| format!("{:.2}", x.time.as_secs_f64() * 1e3 / fills as f64))
            .collect();
        let recv: Vec<u64> = st.iter().map(|x| x.received / fills).collect();
        eprintln!(
            "{n} subdomains: {t:.2} ms/step; exchange (halo fills + step-size maxima) per step \
             and rank: {ex_ms:?} ms, halo particles received per fill {recv:?}, counts {:?}",
            d.counts()
        );
    }
}
