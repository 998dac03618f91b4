//! Colour maps of the plots.
//!
//! - [`diverging`]: signed values in `[−1, 1]` (the velocities of the space–time maps, paper
//!   Figs. 4, 6, 10, 13): Moreland's "smooth cool–warm" map (K. Moreland, *Diverging Color Maps
//!   for Scientific Visualization*, ISVC 2009), built by interpolating in his Msh space (polar
//!   CIELAB) from blue `(59, 76, 192)` through a neutral light grey to red `(180, 4, 38)`. The
//!   lightness rises monotonically to the centre and falls after it, so equal steps in value are
//!   close to equal perceived steps, and the sign is the hue (blue < 0 < red).
//! - [`sequential`]: values in `[0, 1]` (magnitudes, 2-D parameter maps): viridis (matplotlib's
//!   perceptually uniform map), linear interpolation of its 11 published control colours.
//!
//! Both are evaluated through a 256-entry lookup table built once (deterministic arithmetic, so
//! identical inputs give identical pixels).

use plotters::style::RGBColor;
use std::sync::OnceLock;

/// Colour of a cell without data (no frame in a time row, no CSV row at a grid point).
pub const NO_DATA: RGBColor = RGBColor(255, 255, 255);

/// Entries of the lookup tables.
const LUT: usize = 256;

/// Viridis at 0, 0.1, …, 1.
const VIRIDIS: [(u8, u8, u8); 11] = [
    (0x44, 0x01, 0x54),
    (0x48, 0x24, 0x75),
    (0x41, 0x44, 0x87),
    (0x35, 0x5f, 0x8d),
    (0x2a, 0x78, 0x8e),
    (0x21, 0x91, 0x8c),
    (0x22, 0xa8, 0x84),
    (0x44, 0xbf, 0x70),
    (0x7a, 0xd1, 0x51),
    (0xbd, 0xdf, 0x26),
    (0xfd, 0xe7, 0x25),
];

/// Index into a lookup table for `s ∈ [0, 1]` (clamped; NaN gives 0).
fn lut_index(s: f64) -> usize {
    let s = if s.is_nan() { 0.0 } else { s.clamp(0.0, 1.0) };
    ((s * (LUT - 1) as f64).round() as usize).min(LUT - 1)
}

/// Diverging colour of `s ∈ [−1, 1]` (clamped): blue for negative, light grey at 0, red for
/// positive. NaN gives [`NO_DATA`].
pub fn diverging(s: f64) -> RGBColor {
    static TABLE: OnceLock<Vec<RGBColor>> = OnceLock::new();
    if s.is_nan() {
        return NO_DATA;
    }
    let t = TABLE.get_or_init(|| {
        (0..LUT)
            .map(|k| cool_warm(k as f64 / (LUT - 1) as f64))
            .collect()
    });
    t[lut_index((s + 1.0) / 2.0)]
}

/// Sequential colour of `s ∈ [0, 1]` (clamped): dark violet (0) to yellow (1). NaN gives
/// [`NO_DATA`].
pub fn sequential(s: f64) -> RGBColor {
    if s.is_nan() {
        return NO_DATA;
    }
    let x = s.clamp(0.0, 1.0) * 10.0;
    let k = (x.floor() as usize).min(9);
    let f = x - k as f64;
    let (a, b) = (VIRIDIS[k], VIRIDIS[k + 1]);
    let mix = |p: u8, q: u8| (p as f64 + f * (q as f64 - p as f64)).round() as u8;
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

// ---- Moreland's Msh interpolation ----

/// Reference white (D65) of the CIELAB conversion, as in Moreland's paper.
const WHITE: [f64; 3] = [0.9505, 1.0, 1.089];

fn srgb_to_lab(c: (u8, u8, u8)) -> [f64; 3] {
    let lin = |v: u8| {
        let v = v as f64 / 255.0;
        if v <= 0.04045 {
            v / 12.92
        } else {
            ((v + 0.055) / 1.055).powf(2.4)
        }
    };
    let (r, g, b) = (lin(c.0), lin(c.1), lin(c.2));
    let xyz = [
        0.4124 * r + 0.3576 * g + 0.1805 * b,
        0.2126 * r + 0.7152 * g + 0.0722 * b,
        0.0193 * r + 0.1192 * g + 0.9505 * b,
    ];
    let f = |t: f64| {
        if t > 0.008856 {
            t.cbrt()
        } else {
            7.787 * t + 16.0 / 116.0
        }
    };
    let (fx, fy, fz) = (
        f(xyz[0] / WHITE[0]),
        f(xyz[1] / WHITE[1]),
        f(xyz[2] / WHITE[2]),
    );
    [116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)]
}

fn lab_to_srgb(lab: [f64; 3]) -> RGBColor {
    let fy = (lab[0] + 16.0) / 116.0;
    let fx = fy + lab[1] / 500.0;
    let fz = fy - lab[2] / 200.0;
    let inv = |f: f64| {
        let c = f * f * f;
        if c > 0.008856 {
            c
        } else {
            (f - 16.0 / 116.0) / 7.787
        }
    };
    let (x, y, z) = (inv(fx) * WHITE[0], inv(fy) * WHITE[1], inv(fz) * WHITE[2]);
    let lin = [
        3.2406 * x - 1.5372 * y - 0.4986 * z,
        -0.9689 * x + 1.8758 * y + 0.0415 * z,
        0.0557 * x - 0.2040 * y + 1.0570 * z,
    ];
    let enc = |v: f64| {
        let v = v.clamp(0.0, 1.0);
        let s = if v <= 0.0031308 {
            12.92 * v
        } else {
            1.055 * v.powf(1.0 / 2.4) - 0.055
        };
        (s * 255.0).round().clamp(0.0, 255.0) as u8
    };
    RGBColor(enc(lin[0]), enc(lin[1]), enc(lin[2]))
}

fn lab_to_msh(l: [f64; 3]) -> [f64; 3] {
    let m = (l[0] * l[0] + l[1] * l[1] + l[2] * l[2]).sqrt();
    let s = if m > 0.0 { (l[0] / m).acos() } else { 0.0 };
    [m, s, l[2].atan2(l[1])]
}

fn msh_to_lab(c: [f64; 3]) -> [f64; 3] {
    [
        c[0] * c[1].cos(),
        c[0] * c[1].sin() * c[2].cos(),
        c[0] * c[1].sin() * c[2].sin(),
    ]
}

/// Hue for the unsaturated end next to a saturated colour (Moreland's hue spin).
fn adjust_hue(sat: [f64; 3], m_unsat: f64) -> f64 {
    if sat[0] >= m_unsat {
        return sat[2];
    }
    let spin = sat[1] * (m_unsat * m_unsat - sat[0] * sat[0]).sqrt() / (sat[0] * sat[1].sin());
    if sat[2] > -std::f64::consts::FRAC_PI_3 {
        sat[2] + spin
    } else {
        sat[2] - spin
    }
}

/// Moreland's cool–warm map at `x ∈ [0, 1]`.
fn cool_warm(x: f64) -> RGBColor {
    let mut m1 = lab_to_msh(srgb_to_lab((59, 76, 192)));
    let mut m2 = lab_to_msh(srgb_to_lab((180, 4, 38)));
    let mut x = x;
    let mid = m1[0].max(m2[0]).max(88.0);
    if x < 0.5 {
        m2 = [mid, 0.0, 0.0];
        x *= 2.0;
    } else {
        m1 = [mid, 0.0, 0.0];
        x = 2.0 * x - 1.0;
    }
    if m1[1] < 0.05 && m2[1] > 0.05 {
        m1[2] = adjust_hue(m2, m1[0]);
    } else if m2[1] < 0.05 && m1[1] > 0.05 {
        m2[2] = adjust_hue(m1, m2[0]);
    }
    let c = [
        (1.0 - x) * m1[0] + x * m2[0],
        (1.0 - x) * m1[1] + x * m2[1],
        (1.0 - x) * m1[2] + x * m2[2],
    ];
    lab_to_srgb(msh_to_lab(c))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn diverging_ends_centre_and_sign() {
        // the end points reproduce Moreland's colours to ±1 per channel (round trip through Lab)
        let lo = diverging(-1.0);
        let hi = diverging(1.0);
        assert!(
            (lo.0 as i32 - 59).abs() <= 1 && (lo.2 as i32 - 192).abs() <= 1,
            "{lo:?}"
        );
        assert!(
            (hi.0 as i32 - 180).abs() <= 1 && (hi.1 as i32 - 4).abs() <= 1,
            "{hi:?}"
        );
        // centre: neutral light grey (channels within 3 of each other, all > 200)
        let c = diverging(0.0);
        assert!(c.0 > 200 && c.1 > 200 && c.2 > 200, "{c:?}");
        assert!((c.0 as i32 - c.2 as i32).abs() <= 3, "{c:?}");
        for k in 1..=10 {
            let s = k as f64 / 10.0;
            let (p, n) = (diverging(s), diverging(-s));
            assert!(p.0 > p.2, "positive {s} must be red: {p:?}");
            assert!(n.2 > n.0, "negative {s} must be blue: {n:?}");
        }
        assert_eq!(diverging(f64::NAN), NO_DATA);
        assert_eq!(diverging(7.0), hi);
    }

    #[test]
    fn diverging_lightness_monotone_per_half() {
        let l = |s: f64| {
            let c = diverging(s);
            srgb_to_lab((c.0, c.1, c.2))[0]
        };
        for k in 0..50 {
            let (a, b) = (k as f64 / 50.0, (k + 1) as f64 / 50.0);
            // lightness falls away from the centre on both sides (allowing 0.5 L* of rounding)
            assert!(l(b) <= l(a) + 0.5, "L({b}) > L({a})");
            assert!(l(-b) <= l(-a) + 0.5, "L(-{b}) > L(-{a})");
        }
    }

    #[test]
    fn sequential_control_points() {
        assert_eq!(sequential(0.0), RGBColor(0x44, 0x01, 0x54));
        assert_eq!(sequential(1.0), RGBColor(0xfd, 0xe7, 0x25));
        assert_eq!(sequential(0.5), RGBColor(0x21, 0x91, 0x8c));
        assert_eq!(sequential(f64::NAN), NO_DATA);
    }
}
