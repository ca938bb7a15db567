/// Control points of the colour map: blue at 0, through purple and pink, to red at 1.
const STOPS: [(f32, [f32; 3]); 4] = [
    (0.0, [0.10, 0.25, 0.95]),  // blue
    (0.35, [0.55, 0.22, 0.85]), // purple
    (0.7, [1.00, 0.45, 0.75]),  // pink
    (1.0, [1.00, 0.08, 0.08]),  // red
];

/// The particle colour map: `t` in 0..1 (clamped; NaN counts as 0) to linear
/// RGB in 0..1. Blue at 0, through purple and pink, to red at 1. The GPU
/// samples a 256-texel table built from this function, so this is the only
/// definition.
pub fn colormap(t: f32) -> [f32; 3] {
    let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
    for w in STOPS.windows(2) {
        let (t0, c0) = w[0];
        let (t1, c1) = w[1];
        if t <= t1 {
            let s = (t - t0) / (t1 - t0);
            return [
                c0[0] + (c1[0] - c0[0]) * s,
                c0[1] + (c1[1] - c0[1]) * s,
                c0[2] + (c1[2] - c0[2]) * s,
            ];
        }
    }
    STOPS[STOPS.len() - 1].1
}

/// The colour map as `n` RGBA8 texels, for the GPU.
pub(crate) fn colormap_table(n: usize) -> Vec<u8> {
    let mut out = Vec::with_capacity(n * 4);
    for i in 0..n {
        let c = colormap(i as f32 / (n - 1) as f32);
        out.extend(c.iter().map(|v| (v * 255.0).round() as u8));
        out.push(255);
    }
    out
}

/// Short text for a colour-bar value.
pub(crate) fn fmt_value(v: f32) -> String {
    let a = v.abs();
    if a == 0.0 {
        "0".into()
    } else if (1e-2..1e4).contains(&a) {
        let d = (3 - a.log10().floor() as i32).clamp(0, 4) as usize;
        format!("{v:.d$}")
    } else {
        format!("{v:.2e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn endpoints_are_blue_and_red() {
        let lo = colormap(0.0);
        assert!(lo[2] > 0.9 && lo[0] < 0.2, "{lo:?}");
        let hi = colormap(1.0);
        assert!(hi[0] > 0.95 && hi[1] < 0.1 && hi[2] < 0.1, "{hi:?}");
    }

    #[test]
    fn passes_purple_then_pink() {
        let purple = colormap(0.35);
        assert!(
            purple[0] > 0.4 && purple[2] > 0.7 && purple[1] < 0.3,
            "{purple:?}"
        );
        let pink = colormap(0.7);
        assert!(pink[0] > 0.9 && pink[2] > 0.6 && pink[1] > 0.3, "{pink:?}");
    }

    #[test]
    fn clamps_and_is_monotone_in_red_and_blue() {
        assert_eq!(colormap(-1.0), colormap(0.0));
        assert_eq!(colormap(2.0), colormap(1.0));
        assert_eq!(colormap(f32::NAN), colormap(0.0));
        let mut prev = colormap(0.0);
        for i in 1..=100 {
            let c = colormap(i as f32 / 100.0);
            assert!(c[0] >= prev[0] - 1e-6, "red must not decrease");
            assert!(c[2] <= prev[2] + 1e-6, "blue must not increase");
            assert!(c.iter().all(|v| (0.0..=1.0).contains(v)));
            prev = c;
        }
    }

    #[test]
    fn table_matches_function() {
        let t = colormap_table(256);
        assert_eq!(t.len(), 1024);
        assert_eq!(&t[0..4], &[26, 64, 242, 255]);
        assert_eq!(&t[1020..1024], &[255, 20, 20, 255]);
    }
}
