//! `meshfree compare`: particle CSV round trip, matching by id and by position, error norms.

use meshfree::compare::{compare, compare_files, MatchBy};
use meshfree::output::{read_particles_csv, write_particles_csv};
use meshfree_core::frame::FrameData;
use meshfree_core::scene::Scene;

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
    let fields = scene.file.output.fields(false);
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
