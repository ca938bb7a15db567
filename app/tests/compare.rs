//! `meshfree compare`: particle CSV round trip, matching by id and by position, error norms.

use meshfree::compare::{compare, compare_files, MatchBy};
use meshfree::output::{read_particles_csv, write_particles_csv};
use meshfree_core::scene::Scene;
use meshfree_core::solver::frame::{Field, FrameData};

#[test]
fn csv_round_trips_and_compares() {
    let ps = Scene::builtin("tank-2d")
        .unwrap()
        .setup()
        .unwrap()
        .particles;
    let dir = tempfile::tempdir().unwrap();
    let a = dir.path().join("a.csv");
    let scene = Scene::builtin("tank-2d").unwrap();
    // Matching by id needs the `id` field, which the default fields leave out.
    let fields = scene.file.output.fields(&ps).with(Field::Id);
    write_particles_csv(&a, &FrameData::from_particles(&ps, fields, 0, 0.0), fields).unwrap();
    let back = read_particles_csv(&a).unwrap();
    assert_eq!(back.len(), ps.len());
    assert_eq!(back[17].position, ps[17].position);
    assert_eq!(back[17].kind, ps[17].kind);

    // Identical files: every norm zero.
    let same = compare_files(&a, &a, MatchBy::Id, 3).unwrap();
    assert_eq!(same.matched, ps.len());
    assert!(
        same.fields.iter().all(|f| f.max_abs == 0.0),
        "{:?}",
        same.fields
    );

    // One particle's pressure off by 5: max |A - B| is 5 and names it.
    let mut b = ps.clone();
    b[40].pressure += 5.0;
    let c = compare(&b, &ps, MatchBy::Id, 3);
    let p = c.fields.iter().find(|f| f.field == "pressure").unwrap();
    assert!(
        (p.max_abs - 5.0).abs() < 1e-3 && p.worst_id == ps[40].id,
        "{p:?}"
    );

    // Another code's export: other ids and order, positions shifted by a tenth of dx.
    let mut other = ps.clone();
    other.reverse();
    for (k, q) in other.iter_mut().enumerate() {
        q.id = 1_000_000 + k as u32;
        q.position[0] += 0.0025;
    }
    let c = compare(&other, &ps, MatchBy::Position, 2);
    assert_eq!(c.matched, ps.len());
    let x = c.fields.iter().find(|f| f.field == "x").unwrap();
    assert!(
        (x.max_abs - 0.0025).abs() < 1e-5,
        "nearest-position pairs are the shifted twins: {x:?}"
    );
    let by_id = compare(&other, &ps, MatchBy::Id, 2);
    assert_eq!(by_id.matched, 0, "no id in common");
}

#[test]
fn bad_csv_names_file_line_and_field() {
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("bad.csv");
    std::fs::write(
        &f,
        "id,kind,x,y,z,vx,vy,vz,density,pressure\n0,fluid,0,0,0,0,0,0,1000,zero\n",
    )
    .unwrap();
    let e = read_particles_csv(&f).unwrap_err();
    assert!(
        e.contains("bad.csv") && e.contains("line 2") && e.contains("`pressure`"),
        "{e}"
    );
}

/// A fluid particle of id `id` at `x`.
fn at(id: u32, x: [f32; 3]) -> meshfree_core::physics::particle::Particle {
    meshfree_core::physics::particle::Particle {
        id,
        kind: meshfree_core::physics::particle::Kind::Fluid,
        group: 0,
        position: x,
        velocity: [0.0; 3],
        density: 1000.0,
        pressure: 0.0,
        mass: 1.0,
        stress: [0.0; 6],
    }
}

/// xorshift64*, seeded: the same points on every machine.
fn points(n: usize, seed: u64, scale: f32) -> Vec<[f32; 3]> {
    let mut s = seed;
    let mut r = move || {
        s ^= s >> 12;
        s ^= s << 25;
        s ^= s >> 27;
        (s.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 40) as f32 / (1u64 << 24) as f32 * scale
    };
    (0..n).map(|_| [r(), r(), 0.5 * r()]).collect()
}

#[test]
fn position_matching_finds_the_nearest_like_a_search_of_all() {
    let a: Vec<_> = (points(1500, 7, 1.0).into_iter().enumerate())
        .map(|(i, x)| at(i as u32, x))
        .collect();
    let b: Vec<_> = (points(1000, 11, 1.2).into_iter().enumerate())
        .map(|(i, x)| at(i as u32, x))
        .collect();
    let c = compare(&a, &b, MatchBy::Position, a.len());
    assert_eq!(c.matched, a.len());
    let d = |p: &[f32; 3], q: &[f32; 3]| {
        (0..3)
            .map(|k| (p[k] as f64 - q[k] as f64).powi(2))
            .sum::<f64>()
            .sqrt()
    };
    for &(ia, _, dist) in &c.worst_positions {
        let p = &a[ia as usize].position;
        let best = b.iter().map(|q| d(p, &q.position)).fold(f64::MAX, f64::min);
        assert_eq!(dist, best, "particle {ia}");
    }
}

#[test]
fn position_matching_is_not_quadratic() {
    // Issue #52: 2,026 rows against an empty side took 119 s, 500 coincident points 55 s
    // (a widening search of up to 64 rings of cells per particle). At 20,000 each, a
    // search per particle that reads all of the other side takes minutes.
    let a: Vec<_> = (points(20_000, 3, 1.0).into_iter().enumerate())
        .map(|(i, x)| at(i as u32, x))
        .collect();
    let c = compare(&a, &[], MatchBy::Position, 5);
    assert_eq!((c.matched, c.only_in_a), (0, a.len()));
    // All of B at one point, far from A: every particle of A finds it.
    let b: Vec<_> = (0..20_000).map(|i| at(i, [50.0, 50.0, 0.0])).collect();
    let c = compare(&a, &b, MatchBy::Position, 5);
    assert_eq!(c.matched, a.len());
    // And the other way: each of the coincident points finds its nearest in A.
    let c = compare(&b, &a, MatchBy::Position, 5);
    assert_eq!(c.matched, b.len());
    // Positions that are not numbers match nothing.
    let nan = vec![at(0, [f32::NAN, 0.0, 0.0])];
    assert_eq!(compare(&nan, &a, MatchBy::Position, 1).matched, 0);
    assert_eq!(compare(&a[..3], &nan, MatchBy::Position, 1).matched, 0);
}
