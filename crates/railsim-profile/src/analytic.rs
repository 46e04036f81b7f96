//! Analytic reference profiles: S1002 wheel (EN 13715) and UIC60 (60E1) rail head.
//!
//! * S1002: the piecewise definition of EN 13715 / UIC 510-2 with the widely circulated DLR
//!   coefficient set (H. Netter), as listed in contact-theory §5.1. It reproduces the Manchester
//!   benchmark file `MBench_S1002_v3.prw` to about 2e-6 mm.
//! * UIC60: a reconstruction of the head (R300 crown, R80, R13 gauge corner, 1:20 flank) fitted
//!   to the benchmark file `MBench_UIC60_v3.prr` (contact-theory §5.2). It is not a
//!   transcription of EN 13674-1.

use crate::{Profile, ProfileKind};

/// Section A, field-side 1:15 cone: lower limit \[mm\].
const S_AB: f64 = 32.15796;
const S_BC: f64 = -26.0;
const S_CD: f64 = -35.0;
const S_DE: f64 = -38.426669071;
const S_EF: f64 = -39.764473993;
const S_FG: f64 = -49.662510381;
const S_GH: f64 = -62.764705882;

const B: [f64; 9] = [
    0.0,
    -3.358537058e-2,
    1.565681624e-3,
    -2.810427944e-5,
    5.844240864e-8,
    -1.562379023e-8,
    5.309217349e-15,
    -5.957839843e-12,
    2.646656573e-13,
];
const C: [f64; 8] = [
    -4.320221063e3,
    -1.038384026e3,
    -1.065501873e2,
    -6.051367875,
    -2.054332446e-1,
    -4.169739389e-3,
    -4.687195829e-5,
    -2.252755540e-7,
];

fn poly(c: &[f64], s: f64) -> f64 {
    c.iter().rev().fold(0.0, |acc, &k| acc * s + k)
}

fn circ(r: f64, d: f64) -> f64 {
    (r * r - d * d).max(0.0).sqrt()
}

/// The S1002 sections as individual formulas (section index 0 = A ... 7 = H), evaluated
/// without range checks, so they can be extended slightly past their breakpoints.
fn section(k: usize, s: f64) -> f64 {
    match k {
        0 => 1.364323640 - 0.066666667 * s,
        1 => poly(&B, s),
        2 => poly(&C, s),
        3 => 16.446 - circ(13.0, s + 26.210665),
        4 => -93.576667419 - 2.747477419 * s,
        5 => 8.834924130 + circ(20.0, s + 58.558326413),
        6 => 16.0 + circ(12.0, s + 55.0),
        _ => 9.519259302 + circ(20.5, s + 49.5),
    }
}

fn section_index(s: f64) -> usize {
    if s >= S_AB {
        0
    } else if s >= S_BC {
        1
    } else if s >= S_CD {
        2
    } else if s >= S_DE {
        3
    } else if s >= S_EF {
        4
    } else if s >= S_FG {
        5
    } else if s >= S_GH {
        6
    } else {
        7
    }
}

/// S1002 wheel profile F(S) \[mm\] at S \[mm\] (EN 13715 / UIC 510-2, DLR coefficients).
///
/// S is lateral from the measuring circle, positive toward the field side (flange back at
/// S = -70); F is the radial offset from the measuring-circle radius, positive downward (flange
/// tip F = 28 at S = -55), so the radius is r0 + F. Defined for -70 <= S <= 60; NaN outside.
/// This is the exact piecewise definition, including the coefficient-rounding mismatches at
/// the breakpoints (1.2e-4 mm at S = -35, 3.6e-5 mm at S = -26); see [`s1002_f_blended`].
pub fn s1002_f(s_mm: f64) -> f64 {
    if !(-70.0..=60.0).contains(&s_mm) {
        return f64::NAN;
    }
    section(section_index(s_mm), s_mm)
}

/// Half width \[mm\] of the blending zones at the S1002 breakpoints S = -26 and S = -35.
pub const S1002_BLEND_HALF_WIDTH_MM: f64 = 0.05;

/// [`s1002_f`] with the two breakpoint mismatches (S = -26 and S = -35) blended over
/// ±[`S1002_BLEND_HALF_WIDTH_MM`] by a C² quintic smoothstep between the adjacent section
/// formulas (contact-theory §7.3 pitfall 4). Differs from [`s1002_f`] by at most 1.2e-4 mm.
pub fn s1002_f_blended(s_mm: f64) -> f64 {
    let h = S1002_BLEND_HALF_WIDTH_MM;
    for (b, left, right) in [(S_BC, 2, 1), (S_CD, 3, 2)] {
        if (s_mm - b).abs() < h {
            let t = (s_mm - (b - h)) / (2.0 * h);
            let w = t * t * t * (10.0 + t * (-15.0 + 6.0 * t));
            return (1.0 - w) * section(left, s_mm) + w * section(right, s_mm);
        }
    }
    s1002_f(s_mm)
}

/// The S1002 wheel profile in the crate's wheel frame: y = S, z = -F(S) \[m\], sampled every
/// 0.05 mm in y from -70 mm (flange back) to +60 mm (field side), 2601 points, with the
/// breakpoint mismatches blended ([`s1002_f_blended`]).
pub fn s1002() -> Profile {
    let n = 2600;
    let points = (0..=n)
        .map(|i| {
            let s = -70.0 + 130.0 * i as f64 / n as f64;
            [s * 1e-3, -s1002_f_blended(s) * 1e-3]
        })
        .collect();
    Profile {
        name: "S1002 (analytic, EN 13715)".into(),
        kind: ProfileKind::Wheel,
        points,
    }
}

/// Geometry of the reconstructed UIC60 head (mm, u lateral, z_d downward from the crown top).
pub(crate) mod uic {
    /// Crown radius \[mm\].
    pub const R_CROWN: f64 = 300.0;
    /// Second radius \[mm\].
    pub const R_80: f64 = 80.0;
    /// Gauge-corner radius \[mm\].
    pub const R_13: f64 = 13.0;
    /// Lateral end of the crown arc \[mm\].
    pub const U_CROWN_END: f64 = 10.5;
    /// Half head width at the R13/flank tangency \[mm\].
    pub const HALF_WIDTH: f64 = 36.0;
    /// Depth \[mm\] below the crown at which the analytic flank stops.
    pub const ZD_MAX: f64 = 38.0;

    /// Derived data: (R80 centre, R13 centre, R80/R13 tangency u, flank tangency (u, z_d)).
    pub fn derived() -> ([f64; 2], [f64; 2], f64, [f64; 2]) {
        let zc_end = R_CROWN - (R_CROWN * R_CROWN - U_CROWN_END * U_CROWN_END).sqrt();
        let k = (R_CROWN - R_80) / R_CROWN;
        let c80 = [U_CROWN_END * k, R_CROWN + (zc_end - R_CROWN) * k];
        // Flank direction (du, dz_d) = (1, 20)/|.|; outward normal (20, -1)/|.|.
        let n = 401f64.sqrt();
        let u13 = HALF_WIDTH - R_13 * 20.0 / n;
        let d = R_80 - R_13;
        let z13 = c80[1] - (d * d - (u13 - c80[0]).powi(2)).sqrt();
        let c13 = [u13, z13];
        let u_80_13 = c80[0] + (c13[0] - c80[0]) * R_80 / d;
        let tang = [c13[0] + R_13 * 20.0 / n, c13[1] - R_13 / n];
        (c80, c13, u_80_13, tang)
    }
}

/// UIC60 (60E1) head depth z_d \[mm\], downward from the crown top, at lateral position u \[mm\]
/// from the rail's symmetry axis (uncanted, symmetric), or `None` where the analytic head is not
/// defined (|u| beyond the flank at z_d = 38 mm, about 37.19 mm).
///
/// Elements (contact-theory §5.2): R300 crown for |u| <= 10.5, R80 (centre (±7.7, 80.1348)) to
/// |u| = 25.988, R13 gauge corner (centre (±23.0162, 14.9089)) to the flank tangency at
/// |u| = 36.000, z_d = 14.2597, then the 1:20 flank. Centres are derived from the tangency
/// conditions, so the outline is exactly G1.
pub fn uic60_head_zd(u_mm: f64) -> Option<f64> {
    use uic::*;
    let a = u_mm.abs();
    if !a.is_finite() {
        return None;
    }
    let (c80, c13, u_80_13, tang) = derived();
    if a <= U_CROWN_END {
        Some(R_CROWN - circ(R_CROWN, a))
    } else if a <= u_80_13 {
        Some(c80[1] - circ(R_80, a - c80[0]))
    } else if a <= tang[0] {
        Some(c13[1] - circ(R_13, a - c13[0]))
    } else {
        let zd = tang[1] + 20.0 * (a - tang[0]);
        (zd <= ZD_MAX).then_some(zd)
    }
}

/// The analytic UIC60 head as a rail profile: uncanted, symmetric, y = u toward the field side,
/// z = -z_d up, origin at the crown top on the symmetry axis. Sampled along the outline every
/// 0.05 mm or less of arc length (each element gets a whole number of intervals, so the
/// tangency points are samples), from z_d = 38 mm on the gauge side to the same depth on the
/// field side.
pub fn uic60() -> Profile {
    use uic::*;
    let (c80, c13, u_80_13, tang) = derived();
    let ds = 0.05;
    // Half outline from the axis to the flank end (u >= 0), as (u, z_d) samples, u increasing.
    let mut half: Vec<[f64; 2]> = vec![[0.0, 0.0]];
    let arc = |c: [f64; 2], r: f64, u0: f64, u1: f64, out: &mut Vec<[f64; 2]>| {
        // Angles measured from the upward direction (-z_d): point = c + r (sin t, -cos t).
        let t0 = ((u0 - c[0]) / r).asin();
        let t1 = ((u1 - c[0]) / r).asin();
        let n = ((r * (t1 - t0)) / ds).ceil().max(1.0) as usize;
        for i in 1..=n {
            let t = t0 + (t1 - t0) * i as f64 / n as f64;
            out.push([c[0] + r * t.sin(), c[1] - r * t.cos()]);
        }
    };
    arc([0.0, R_CROWN], R_CROWN, 0.0, U_CROWN_END, &mut half);
    arc(c80, R_80, U_CROWN_END, u_80_13, &mut half);
    arc(c13, R_13, u_80_13, tang[0], &mut half);
    let flank_len = (ZD_MAX - tang[1]) * (401f64).sqrt() / 20.0;
    let n = (flank_len / ds).ceil() as usize;
    for i in 1..=n {
        let zd = tang[1] + (ZD_MAX - tang[1]) * i as f64 / n as f64;
        half.push([tang[0] + (zd - tang[1]) / 20.0, zd]);
    }
    let mut points: Vec<[f64; 2]> = half
        .iter()
        .rev()
        .map(|p| [-p[0] * 1e-3, -p[1] * 1e-3])
        .collect();
    points.extend(half.iter().skip(1).map(|p| [p[0] * 1e-3, -p[1] * 1e-3]));
    Profile {
        name: "UIC60 head (analytic reconstruction)".into(),
        kind: ProfileKind::Rail,
        points,
    }
}
