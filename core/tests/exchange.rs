//! Domain decomposition (`meshfree_core::exchange`): N subdomains stepping together equal
//! the one-domain run, bit for bit in every particle's position, velocity, density,
//! pressure and stress (the same (cell, id) neighbour order, the same agreed step), on 2D
//! and 3D scenes with walls, a gate, elastic bodies, a periodic axis with an inflow band,
//! and the paper's summation density and forward Euler; the diagnostics' sums to round-off;
//! wall forces, probes and a save / restore across the decomposition.

mod common;

use meshfree_core::backend::{self, BackendChoice};
use meshfree_core::exchange::{balanced, halo_width, longest_axis, Slab};
use meshfree_core::physics::particle::Particle;
use meshfree_core::solver::Persist;
use meshfree_core::solver::Readback;

use common::edited_scene as scene;
use meshfree_core::solver::{Setup, Solver};

/// Run `setup` for `steps` steps on the CPU in `n` subdomains (0: one domain, no
/// decomposition), gates opened first; the particles by id and the solver.
fn run(setup: &Setup, gates: &[u32], n: usize, steps: u64) -> (Vec<Particle>, Box<dyn Solver>) {
    let mut s = if n == 0 {
        backend::create(BackendChoice::Cpu, backend::Layout::One, setup.clone()).unwrap()
    } else {
        backend::create(
            BackendChoice::Cpu,
            backend::Layout::Threads(n),
            setup.clone(),
        )
        .unwrap()
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
    for (p, q) in a.iter().zip(b) {
        let fields: [(&str, Vec<u32>, Vec<u32>); 5] = [
            ("position", bits(&p.position), bits(&q.position)),
            ("velocity", bits(&p.velocity), bits(&q.velocity)),
            ("density", bits(&[p.density]), bits(&[q.density])),
            ("pressure", bits(&[p.pressure]), bits(&[q.pressure])),
            ("stress", bits(&p.stress), bits(&q.stress)),
        ];
        if p.id != q.id {
            return Err(format!("particle {} against {}", p.id, q.id));
        }
        if let Some((what, _, _)) = fields.iter().find(|f| f.1 != f.2) {
            return Err(format!(
                "particle {} ({:?}) differs in {what}: {p:?}\nagainst {q:?}",
                p.id, p.kind
            ));
        }
    }
    Ok(())
}

/// One domain against 2 and 3 subdomains after `steps` steps: the same bits, and the
/// particles moved (the test stepped something).
fn decomposed_equals_one_domain(name: &str, setup: &Setup, gates: &[u32], steps: u64) {
    let (one, mut s1) = run(setup, gates, 0, steps);
    assert!(
        one.iter()
            .zip(&setup.particles)
            .any(|(a, b)| a.position != b.position),
        "{name}: nothing moved"
    );
    for n in [2, 3] {
        let (many, mut sn) = run(setup, gates, n, steps);
        same(&one, &many).unwrap_or_else(|e| panic!("{name}, {n} subdomains, {steps} steps: {e}"));
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
        assert_eq!(d1.dt.to_bits(), dn.dt.to_bits());
        assert_eq!(d1.max_speed.to_bits(), dn.max_speed.to_bits());
        let rel = (d1.kinetic_energy - dn.kinetic_energy).abs() / d1.kinetic_energy.max(1e-300);
        assert!(
            rel < 1e-12,
            "{name}: kinetic energy {} against {}",
            d1.kinetic_energy,
            dn.kinetic_energy
        );
    }
}

#[test]
fn a_2d_dam_break_in_subdomains_equals_one_domain() {
    let sc = scene("dam-break-2d", &[("spacing = 0.02", "spacing = 0.03")]);
    let gates: Vec<u32> = sc.gates().iter().map(|g| g.0).collect();
    decomposed_equals_one_domain("dam-break-2d", &sc.setup().unwrap(), &gates, 60);
}

#[test]
fn the_paper_scheme_in_subdomains_equals_one_domain() {
    // Summation density (one more neighbour pass in the halo) and the forward Euler.
    let sc = scene("dam-break-2d", &[("spacing = 0.02", "spacing = 0.03")])
        .with_paper_exact()
        .unwrap();
    let gates: Vec<u32> = sc.gates().iter().map(|g| g.0).collect();
    decomposed_equals_one_domain(
        "dam-break-2d --paper-exact",
        &sc.setup().unwrap(),
        &gates,
        60,
    );
}

#[test]
fn a_3d_dam_break_in_subdomains_equals_one_domain() {
    let sc = scene("dam-break-3d", &[("spacing = 0.04", "spacing = 0.05")]);
    let gates: Vec<u32> = sc.gates().iter().map(|g| g.0).collect();
    decomposed_equals_one_domain("dam-break-3d", &sc.setup().unwrap(), &gates, 30);
}

#[test]
fn elastic_bodies_and_a_gate_in_subdomains_equal_one_domain() {
    let sc = scene(
        "impinging-2d",
        &[
            ("spacing = 0.375", "spacing = 0.75"),
            ("layers = 3", "layers = 2"),
        ],
    );
    let gates: Vec<u32> = sc.gates().iter().map(|g| g.0).collect();
    let setup = sc.setup().unwrap();
    assert!(setup.has_solids());
    decomposed_equals_one_domain("impinging-2d", &setup, &gates, 60);
}

#[test]
fn a_periodic_channel_with_inflow_in_subdomains_equals_one_domain() {
    // Cut along x, the periodic axis: the first and last slabs are neighbours round it.
    let sc = scene(
        "vortex-street-re105",
        &[("spacing = 0.06", "spacing = 0.15")],
    );
    let setup = sc.setup().unwrap();
    assert_eq!(longest_axis(&setup.params), 0);
    assert!(setup.params.periodic[0] != 0 && setup.params.inflow != 0);
    decomposed_equals_one_domain("vortex-street-re105", &setup, &[], 40);
}

#[test]
fn wall_forces_probes_and_a_restore_work_across_subdomains() {
    let sc = scene(
        "vortex-street-re105",
        &[("spacing = 0.06", "spacing = 0.15")],
    );
    let setup = sc.setup().unwrap();
    let (_, mut one) = run(&setup, &[], 0, 20);
    let (_, mut many) = run(&setup, &[], 3, 20);
    // The cylinder is group 1; its force summed over the owned wall particles of each
    // subdomain, in another order: equal to round-off.
    let (f1, f3) = (one.wall_forces(&[1]), many.wall_forces(&[1]));
    for a in 0..2 {
        let scale = f1[0][0].abs().max(f1[0][1].abs());
        assert!(scale > 0.0);
        assert!(
            (f1[0][a] - f3[0][a]).abs() <= 1e-9 * scale,
            "wall force {f1:?} against {f3:?}"
        );
    }
    // Probes on both sides of every cut see the same particles.
    let slabs = balanced(
        &setup.params,
        0,
        &setup
            .particles
            .iter()
            .map(|q| q.position[0])
            .collect::<Vec<_>>(),
        3,
    );
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
    // decomposition (into 2 subdomains: another cut) steps on as the one domain does.
    one.advance(10);
    many.advance(10);
    same(&one.particles(), &many.particles()).unwrap();
    let saved = many.save();
    let mut two = backend::create(
        BackendChoice::Cpu,
        backend::Layout::Threads(2),
        setup.clone(),
    )
    .unwrap();
    two.restore(&saved).unwrap();
    one.advance(10);
    two.advance(10);
    same(&one.particles(), &two.particles()).unwrap();
    assert_eq!(one.time().to_bits(), two.time().to_bits());
}

#[test]
fn slabs_split_by_count_and_the_halo_covers_the_passes() {
    let sc = scene("dam-break-2d", &[]);
    let setup = sc.setup().unwrap();
    let p = setup.params;
    let axis = longest_axis(&p);
    let xs: Vec<f32> = setup.particles.iter().map(|q| q.position[axis]).collect();
    let slabs = balanced(&p, axis, &xs, 4);
    assert_eq!(slabs.len(), 4);
    assert_eq!(slabs[0].lo, f32::NEG_INFINITY);
    assert_eq!(slabs[3].hi, f32::INFINITY);
    for (k, slab) in slabs.iter().enumerate() {
        let c = xs.iter().filter(|&&x| slab.contains(x)).count();
        assert!(
            c.abs_diff(xs.len() / 4) <= xs.len() / 20,
            "slab {k} holds {c} of {}",
            xs.len()
        );
    }
    // Symplectic Euler with the continuity density: 2 passes and the skin.
    assert_eq!(halo_width(&p), 3.0 * p.support);
    // The gap round a periodic axis takes the shorter way.
    let s = Slab {
        axis: 0,
        lo: 1.0,
        hi: 2.0,
    };
    assert_eq!(s.gap(9.5, Some((0.0, 10.0))), 1.5);
    assert_eq!(s.gap(2.5, Some((0.0, 10.0))), 0.5);
    assert_eq!(s.gap(9.5, None), 7.5);
    assert_eq!(s.gap(1.5, None), 0.0);
}

#[test]
fn total_lagrangian_bodies_are_refused_with_the_reason() {
    let sc = scene(
        "impinging-2d",
        &[
            ("spacing = 0.375", "spacing = 0.75"),
            ("layers = 3", "layers = 2"),
            ("[solid]\n", "[solid]\nformulation = \"total-lagrangian\"\n"),
        ],
    );
    let e = backend::create(
        BackendChoice::Cpu,
        backend::Layout::Threads(2),
        sc.setup().unwrap(),
    )
    .err()
    .expect("refused");
    assert!(e.to_string().contains("total-Lagrangian"), "{e}");
}

#[test]
fn moving_the_cuts_keeps_the_run_exact_and_balances_the_load() {
    use meshfree_core::backend::cpu::CpuSolver;
    use meshfree_core::exchange::{Decomposed, Refused};
    use meshfree_core::physics::dim::D2;
    let sc = scene("dam-break-2d", &[("spacing = 0.02", "spacing = 0.03")]);
    let gates: Vec<u32> = sc.gates().iter().map(|g| g.0).collect();
    let mut setup = sc.setup().unwrap();
    setup.params.own_solids = 0;
    let mut one = backend::create(BackendChoice::Cpu, backend::Layout::One, setup.clone()).unwrap();
    let mut many =
        Decomposed::new(setup, 3, |s| Ok::<_, Refused>(CpuSolver::<D2>::new(s))).unwrap();
    for &g in &gates {
        one.remove_group(g);
        many.remove_group(g);
    }
    // The gate's removal unbalanced the cuts made with it.
    let before = many.imbalance();
    assert!(before > 1.0);
    assert!(many.rebalance(1.0).unwrap(), "the cuts did not move");
    // Whole columns of the lattice go one way or the other: balanced to a few per cent.
    assert!(
        many.imbalance() < before && many.imbalance() < 1.05,
        "{:?}",
        many.counts()
    );
    one.advance(40);
    many.advance(40);
    same(&one.particles(), &many.particles()).unwrap();
    assert!(many.rebalance(1.0).unwrap());
    one.advance(40);
    many.advance(40);
    same(&one.particles(), &many.particles()).unwrap();
    assert_eq!(many.rebalances(), 2);
}

#[test]
fn pieces_saved_per_rank_restore_each_rank_or_gather_into_another_count() {
    use meshfree_core::backend::cpu::CpuSolver;
    use meshfree_core::exchange::{Decomposed, Refused};
    use meshfree_core::physics::dim::D2;
    let sc = scene("dam-break-2d", &[("spacing = 0.02", "spacing = 0.03")]);
    let gates: Vec<u32> = sc.gates().iter().map(|g| g.0).collect();
    let mut setup = sc.setup().unwrap();
    setup.params.own_solids = 0;
    let three = |setup: &Setup| {
        let mut d = Decomposed::new(setup.clone(), 3, |s| {
            Ok::<_, Refused>(CpuSolver::<D2>::new(s))
        })
        .unwrap();
        for &g in &gates {
            d.remove_group(g);
        }
        d
    };
    let mut many = three(&setup);
    many.advance(30);
    // Cuts of its own, other than a fresh start's: the pieces must bring them back.
    assert!(many.rebalance(1.0).unwrap());
    let pieces = many.save_pieces().unwrap();
    assert_eq!(pieces.len(), 3);
    assert_eq!(
        pieces.iter().map(|p| p.slab).collect::<Vec<_>>(),
        many.slabs()
    );
    let mut again = three(&setup);
    assert_ne!(again.slabs(), many.slabs());
    again.restore_pieces(&pieces).unwrap();
    assert_eq!(again.slabs(), many.slabs(), "each rank took its own slab");
    assert_eq!(again.counts(), many.counts());
    many.advance(30);
    again.advance(30);
    same(&many.particles(), &again.particles()).unwrap();
    assert_eq!(
        again.save_pieces(),
        many.save_pieces(),
        "storage and cuts alike"
    );
    // Into another count (one domain, 2 subdomains): the pieces gathered, equally exact.
    let pieces = many.save_pieces().unwrap();
    let mut one = backend::create(BackendChoice::Cpu, backend::Layout::One, setup.clone()).unwrap();
    let mut two = backend::create(
        BackendChoice::Cpu,
        backend::Layout::Threads(2),
        setup.clone(),
    )
    .unwrap();
    for &g in &gates {
        one.remove_group(g);
        two.remove_group(g);
    }
    one.restore_pieces(&pieces).unwrap();
    two.restore_pieces(&pieces).unwrap();
    many.advance(20);
    one.advance(20);
    two.advance(20);
    same(&many.particles(), &one.particles()).unwrap();
    same(&many.particles(), &two.particles()).unwrap();
    // Pieces swapped between ranks, or one from another step, are refused with the reason.
    let mut mixed = many.save_pieces().unwrap();
    mixed.swap(0, 1);
    let e = three(&setup).restore_pieces(&mixed).unwrap_err();
    assert!(e.contains("slabs do not follow"), "{e}");
    let mut mixed = many.save_pieces().unwrap();
    let first = mixed[0].state.clone();
    mixed[0].state = std::mem::replace(&mut mixed[1].state, first);
    let e = three(&setup).restore_pieces(&mixed).unwrap_err();
    assert!(
        e.contains("rank 0's piece") && e.contains("outside its slab"),
        "{e}"
    );
    let mut stale = many.save_pieces().unwrap();
    stale[2].state.steps -= 1;
    let e = three(&setup).restore_pieces(&stale).unwrap_err();
    assert!(e.contains("rank 2's piece") && e.contains("step"), "{e}");
}
