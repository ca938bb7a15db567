//! The lattice Boltzmann reference (`meshfree_lab::lbm`): a body-force-driven channel against
//! Poiseuille's profile, and a short cylinder run's drag.

use meshfree_lab::lbm::street::{Street, U_LATTICE};
use meshfree_lab::lbm::Lattice;
use meshfree_lab::validate::cylinder::blockage_epsilon;

/// A channel of `h` fluid rows between solid rows j = 0 and j = h + 1 (walls at y = 1 and
/// y = h + 1 in lattice units), periodic in x, driven by a uniform acceleration g:
/// u(y) = g / (2 nu) (y - 1)(h + 1 - y). TRT at the magic 3/16 puts bounce-back's walls
/// exactly halfway, so the steady profile is exact to round-off (Ginzburg et al. 2008;
/// Krueger et al. 2017, 10.7), at any tau.
#[test]
fn poiseuille_channel_matches_the_parabola() {
    let h = 8usize;
    for nu in [0.05, 0.5] {
        let g = 1e-6;
        let mut lat = Lattice::new(4, h + 2, nu, |p| p[1] < 1.0 || p[1] > (h + 1) as f64);
        lat.accel = [g, 0.0];
        // Ten diffusion times h^2 / nu: the slowest mode decays by exp(-10 pi^2).
        for _ in 0..(10.0 * (h * h) as f64 / nu) as usize {
            lat.step();
        }
        let peak = g / (2.0 * nu) * (h as f64 / 2.0).powi(2);
        let mut worst: f64 = 0.0;
        for j in 1..=h {
            let y = j as f64 + 0.5;
            let exact = g / (2.0 * nu) * (y - 1.0) * (h as f64 + 1.0 - y);
            let (_, u) = lat.moments(2, j);
            worst = worst.max((u[0] - exact).abs() / peak);
            assert!(u[1].abs() < 1e-9 * peak, "no cross flow: {}", u[1]);
        }
        eprintln!("Poiseuille, nu {nu}: largest error {worst:.2e} of the peak");
        assert!(worst < 1e-6, "nu {nu}: largest error {worst:e} of the peak");
    }
}

/// A short, coarse street at Re 20 (steady, attached eddies) in a wide row (pitch 10 D,
/// blockage 0.1): the mean drag over t U / D = 10-20 within 10 % of the unconfined
/// 2.05 (Tritton 1959's measurement, Dennis & Chang 1970's 2.045) raised by Allen &
/// Vincenti's blockage correction ((1 + eps)^2, eps = 0.056), and no lift.
#[test]
fn a_coarse_cylinder_drags_as_published() {
    let street = Street {
        name: "test",
        re: 20.0,
        length: 30.0,
        height: 20.0,
        diameter: 2.0,
        centre: [10.0, 10.0],
        band: (25.0, 26.0),
        u: 1.0,
        ramp: 4.0,
        t_end: 40.0,
        sample: 0.5,
    };
    let run = street.run(8, U_LATTICE);
    let late: Vec<_> = run.samples.iter().filter(|s| s.t >= 20.0).collect();
    let cd = late.iter().map(|s| s.cd).sum::<f64>() / late.len() as f64;
    let cl = late.iter().map(|s| s.cl.abs()).fold(0.0, f64::max);
    let expected = 2.05 * (1.0 + blockage_epsilon(0.1, 2.05)).powi(2);
    eprintln!(
        "Re 20, D = 8 cells: mean Cd {cd:.4} (expected {expected:.4}), largest |Cl| {cl:.2e}"
    );
    assert!(
        (cd / expected - 1.0).abs() < 0.1,
        "mean Cd {cd:.3} against {expected:.3}"
    );
    assert!(cl < 0.05, "largest |Cl| {cl:.3} at Re 20");
}
