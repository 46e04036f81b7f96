//! Compiled alignment: plan geometry (tangent, clothoid, circular arc), cant and gradient, and
//! its evaluation s → [`TrackFrame`].
//!
//! Plan geometry. Along each segment the curvature is linear in s,
//! κ(u) = κ₀ + κ′ u, so the heading is ψ(u) = ψ₀ + κ₀ u + κ′ u²/2 and the position is
//! x(u) = x₀ + ∫₀ᵘ cos ψ, y(u) = y₀ + ∫₀ᵘ sin ψ. Tangents and arcs (κ′ = 0) use the closed form
//! (chord of length 2 sin(κu/2)/κ along ψ₀ + κu/2). A clothoid (κ′ ≠ 0) is the Euler spiral
//! whose coordinates are Fresnel integrals (Abramowitz & Stegun 7.3; for a spiral from κ = 0,
//! x = a√π C(u/(a√π)), y = a√π S(u/(a√π)) with a² = 1/κ′); here it is integrated with
//! 8-point Gauss–Legendre quadrature from knots precomputed at compile time every ≤ 10 m, which
//! agrees with the Fresnel form to about 1e-12 m (see the tests), works for a spiral between
//! any two curvatures and costs one fixed-size quadrature per lookup.

use crate::math::{GL8_W, GL8_X};

/// \[m\] longest distance integrated by quadrature in one lookup (knot spacing on clothoids).
const KNOT_SPACING_M: f64 = 10.0;

/// Kind of an alignment segment.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SegmentKind {
    /// Straight line: zero curvature, constant cant (normally zero).
    Tangent,
    /// Transition curve (clothoid): curvature and cant linear in s between the neighbours.
    Clothoid,
    /// Circular curve: constant curvature and cant.
    Curve,
}

/// Index of a segment in [`crate::TrackModel::segments`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct SegmentId(pub usize);

/// A compiled segment: everything in SI, start state precomputed.
#[derive(Debug, Clone, PartialEq)]
pub struct Segment {
    /// Tangent, clothoid or curve.
    pub kind: SegmentKind,
    /// \[m\] distance along the track where the segment starts.
    pub s_start: f64,
    /// \[m\] length.
    pub length: f64,
    /// \[1/m\] curvature at the start, positive for a curve to the left.
    pub curvature_start: f64,
    /// \[1/m\] curvature at the end.
    pub curvature_end: f64,
    /// \[m\] cant at the start, as height of the left rail above the right rail.
    pub cant_start: f64,
    /// \[m\] cant at the end, as height of the left rail above the right rail.
    pub cant_end: f64,
    /// \[-\] gradient dz/ds (rise per unit length).
    pub gradient: f64,
    /// \[m\] x of the start point in the ground frame.
    pub x_start: f64,
    /// \[m\] y of the start point in the ground frame.
    pub y_start: f64,
    /// \[m\] z of the start point (before vertical rounding) in the ground frame.
    pub z_start: f64,
    /// \[rad\] heading at the start, from the ground x-axis toward y.
    pub heading_start: f64,
    /// Vertical curve at the start: (\[-\] gradient change, \[m\] half length).
    pub(crate) vjoin_start: Option<(f64, f64)>,
    /// Vertical curve at the end: (\[-\] gradient change, \[m\] half length).
    pub(crate) vjoin_end: Option<(f64, f64)>,
    /// First knot in [`Alignment::knots`] and knot spacing \[m\] (clothoids only).
    knot_first: usize,
    knot_spacing: f64,
}

/// Plan state at a knot.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Knot {
    x: f64,
    y: f64,
    psi: f64,
}

/// The track frame at one position s: where the centre line is and how it turns, banks and
/// climbs, with every d/ds.
///
/// Ground frame `G`: origin at s = 0 on the centre line, x along the initial heading, y to the
/// left, z up. Track frame `T` (see `docs/conventions.md`): x along the track, y left, z up,
/// rolled by [`roll`](Self::roll) about x. Time derivatives are the caller's: d/dt = v · d/ds.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct TrackFrame {
    /// \[m\] distance along the track (plan projection).
    pub s: f64,
    /// \[m\] position of the centre line in the plane of the rail tops, in `G`.
    pub position_g: [f64; 3],
    /// \[rad\] heading ψ: angle of the track x-axis from `G`'s x-axis toward its y-axis.
    /// dψ/ds = [`curvature`](Self::curvature).
    pub heading: f64,
    /// \[1/m\] plan curvature κ = dψ/ds, positive for a curve to the left.
    pub curvature: f64,
    /// \[1/m²\] dκ/ds (non-zero on clothoids).
    pub dcurvature_ds: f64,
    /// \[m\] cant as height of the left rail above the right rail over the cant base: negative
    /// in a left curve banked toward its centre.
    pub cant: f64,
    /// \[-\] d(cant)/ds.
    pub dcant_ds: f64,
    /// \[rad\] roll φ of the track plane about the track x-axis (right-handed: positive lifts
    /// the left rail), φ = asin(cant / cant base).
    pub roll: f64,
    /// \[rad/m\] dφ/ds.
    pub droll_ds: f64,
    /// \[-\] gradient dz/ds, positive uphill.
    pub gradient: f64,
    /// \[1/m\] vertical curvature d²z/ds², positive for a sag (concave up).
    pub vertical_curvature: f64,
}

/// The compiled alignment.
#[derive(Debug, Clone, PartialEq)]
pub struct Alignment {
    pub(crate) segments: Vec<Segment>,
    knots: Vec<Knot>,
    /// \[m\] cant base: distance between rail-head centres on which cant is measured.
    pub(crate) cant_base: f64,
    /// \[m\] total length.
    pub(crate) length: f64,
}

/// Input of [`Alignment::build`]: per segment kind, length, end curvatures, end cants, gradient.
#[derive(Debug, Clone, Copy)]
pub(crate) struct SegmentInput {
    pub kind: SegmentKind,
    pub length: f64,
    pub curvature: (f64, f64),
    pub cant: (f64, f64),
    pub gradient: f64,
}

/// Advance along a constant-curvature arc by `d` from (x, y, ψ).
#[inline]
fn arc(x: f64, y: f64, psi: f64, kappa: f64, d: f64) -> (f64, f64, f64) {
    let half = 0.5 * kappa * d;
    // chord length 2 sin(κd/2)/κ = d · sinc(κd/2), series near 0 to avoid cancellation.
    let chord = if half.abs() < 1e-4 {
        d * (1.0 - half * half / 6.0)
    } else {
        d * half.sin() / half
    };
    let dir = psi + half;
    (
        x + chord * dir.cos(),
        y + chord * dir.sin(),
        psi + kappa * d,
    )
}

/// Integrate (cos ψ, sin ψ) for ψ(v) = ψ₀ + κ₀ v + κ′ v²/2 over v ∈ \[0, d\] with 8-point
/// Gauss–Legendre.
#[inline]
fn spiral_delta(psi0: f64, k0: f64, k1: f64, d: f64) -> (f64, f64) {
    let h = 0.5 * d;
    let (mut cx, mut cy) = (0.0, 0.0);
    for j in 0..4 {
        for sgn in [-1.0, 1.0] {
            let v = h + sgn * GL8_X[j] * h;
            let p = psi0 + v * (k0 + 0.5 * k1 * v);
            let (s, c) = p.sin_cos();
            cx += GL8_W[j] * c;
            cy += GL8_W[j] * s;
        }
    }
    (cx * h, cy * h)
}

impl Alignment {
    /// Chain the segments from s = 0 at the origin with heading 0; `vertical_radius` rounds
    /// gradient changes (half length of each rounding must be checked by the caller).
    pub(crate) fn build(
        inputs: &[SegmentInput],
        cant_base: f64,
        vertical_radius: Option<f64>,
    ) -> Alignment {
        let mut segments = Vec::with_capacity(inputs.len());
        let mut knots = Vec::new();
        let (mut x, mut y, mut psi, mut z, mut s) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for inp in inputs {
            let (k0, k1) = inp.curvature;
            let dk = (k1 - k0) / inp.length;
            let knot_first = knots.len();
            let mut knot_spacing = 0.0;
            if inp.kind == SegmentKind::Clothoid || dk != 0.0 {
                let n = (inp.length / KNOT_SPACING_M).ceil().max(1.0) as usize;
                knot_spacing = inp.length / n as f64;
                let (mut kx, mut ky, mut kpsi) = (x, y, psi);
                for i in 0..=n {
                    knots.push(Knot {
                        x: kx,
                        y: ky,
                        psi: kpsi,
                    });
                    if i < n {
                        let u = i as f64 * knot_spacing;
                        let ku = k0 + dk * u;
                        let (dx, dy) = spiral_delta(kpsi, ku, dk, knot_spacing);
                        kx += dx;
                        ky += dy;
                        let u1 = (i + 1) as f64 * knot_spacing;
                        kpsi = psi + k0 * u1 + 0.5 * dk * u1 * u1;
                    }
                }
            }
            segments.push(Segment {
                kind: inp.kind,
                s_start: s,
                length: inp.length,
                curvature_start: k0,
                curvature_end: k1,
                cant_start: inp.cant.0,
                cant_end: inp.cant.1,
                gradient: inp.gradient,
                x_start: x,
                y_start: y,
                z_start: z,
                heading_start: psi,
                vjoin_start: None,
                vjoin_end: None,
                knot_first,
                knot_spacing,
            });
            if knot_spacing > 0.0 {
                let k = knots[knots.len() - 1];
                x = k.x;
                y = k.y;
                psi = k.psi;
            } else {
                (x, y, psi) = arc(x, y, psi, k0, inp.length);
            }
            z += inp.gradient * inp.length;
            s += inp.length;
        }
        if let Some(rv) = vertical_radius {
            for i in 1..segments.len() {
                let dg = segments[i].gradient - segments[i - 1].gradient;
                if dg != 0.0 {
                    let half = 0.5 * rv * dg.abs();
                    segments[i - 1].vjoin_end = Some((dg, half));
                    segments[i].vjoin_start = Some((dg, half));
                }
            }
        }
        Alignment {
            segments,
            knots,
            cant_base,
            length: s,
        }
    }

    /// Index of the segment containing s (the first or last one outside the track).
    #[inline]
    pub(crate) fn segment_index(&self, s: f64) -> usize {
        // partition_point: number of segments starting at or before s.
        let n = self.segments.partition_point(|seg| seg.s_start <= s);
        n.saturating_sub(1)
    }

    /// Plan state (x, y, ψ) at local u ∈ \[0, L\] of segment `seg`.
    #[inline]
    fn plan_at(&self, seg: &Segment, u: f64) -> (f64, f64, f64) {
        let k0 = seg.curvature_start;
        if seg.knot_spacing == 0.0 {
            return arc(seg.x_start, seg.y_start, seg.heading_start, k0, u);
        }
        let dk = (seg.curvature_end - k0) / seg.length;
        let n_knots = (seg.length / seg.knot_spacing).round() as usize;
        let i = ((u / seg.knot_spacing) as usize).min(n_knots.saturating_sub(1));
        let knot = self.knots[seg.knot_first + i];
        let ui = i as f64 * seg.knot_spacing;
        let d = u - ui;
        let ki = k0 + dk * ui;
        let (dx, dy) = spiral_delta(knot.psi, ki, dk, d);
        let psi = seg.heading_start + u * (k0 + 0.5 * dk * u);
        (knot.x + dx, knot.y + dy, psi)
    }

    /// The track frame at s. Outside \[0, length\] the track continues with the end's curvature,
    /// cant and gradient.
    pub(crate) fn frame_at(&self, s: f64) -> TrackFrame {
        let seg = &self.segments[self.segment_index(s)];
        let u_raw = s - seg.s_start;
        let u = u_raw.clamp(0.0, seg.length);
        let outside = u_raw - u;
        let inv_l = 1.0 / seg.length;
        let dk = (seg.curvature_end - seg.curvature_start) * inv_l;
        let (mut x, mut y, mut psi) = self.plan_at(seg, u);
        let mut kappa = seg.curvature_start + dk * u;
        let mut dkappa = dk;
        let mut cant = seg.cant_start + (seg.cant_end - seg.cant_start) * u * inv_l;
        let mut dcant = (seg.cant_end - seg.cant_start) * inv_l;
        if outside != 0.0 {
            (x, y, psi) = arc(x, y, psi, kappa, outside);
            dkappa = 0.0;
            dcant = 0.0;
            kappa = if outside < 0.0 {
                seg.curvature_start
            } else {
                seg.curvature_end
            };
            cant = if outside < 0.0 {
                seg.cant_start
            } else {
                seg.cant_end
            };
        }
        // Vertical profile: piecewise linear plus parabolic rounding at the joins.
        let mut z = seg.z_start + seg.gradient * u_raw;
        let mut gradient = seg.gradient;
        let mut vcurv = 0.0;
        if outside == 0.0 {
            if let Some((dg, h)) = seg.vjoin_start
                && u < h
            {
                // Join at u = 0, inside its second half: t = u + h ∈ [h, 2h).
                let t = u + h;
                z += dg * (t * t / (4.0 * h) - u);
                gradient += dg * (t / (2.0 * h) - 1.0);
                vcurv = dg / (2.0 * h);
            }
            if let Some((dg, h)) = seg.vjoin_end
                && seg.length - u < h
            {
                // Join at u = L, inside its first half: t = u - L + h ∈ [0, h).
                let t = u - seg.length + h;
                z += dg * t * t / (4.0 * h);
                gradient += dg * t / (2.0 * h);
                vcurv = dg / (2.0 * h);
            }
        }
        let sin_roll = (cant / self.cant_base).clamp(-1.0, 1.0);
        let roll = sin_roll.asin();
        let droll = dcant / (self.cant_base * roll.cos());
        TrackFrame {
            s,
            position_g: [x, y, z],
            heading: psi,
            curvature: kappa,
            dcurvature_ds: dkappa,
            cant,
            dcant_ds: dcant,
            roll,
            droll_ds: droll,
            gradient,
            vertical_curvature: vcurv,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn one(kind: SegmentKind, length: f64, k: (f64, f64)) -> SegmentInput {
        SegmentInput {
            kind,
            length,
            curvature: k,
            cant: (0.0, 0.0),
            gradient: 0.0,
        }
    }

    #[test]
    fn arc_small_and_large_angles_agree_with_definition() {
        let (x, y, p) = arc(0.0, 0.0, 0.3, 1.0 / 500.0, 100.0);
        let (x0, y0) = (
            500.0 * ((0.3f64 + 0.2).sin() - 0.3f64.sin()),
            -500.0 * ((0.3f64 + 0.2).cos() - 0.3f64.cos()),
        );
        assert!((x - x0).abs() < 1e-10 && (y - y0).abs() < 1e-10);
        assert!((p - 0.5).abs() < 1e-15);
        let (x, y, _) = arc(0.0, 0.0, 0.0, 1e-12, 100.0);
        assert!((x - 100.0).abs() < 1e-9 && y.abs() < 1e-8);
    }

    #[test]
    fn clothoid_quadrature_matches_fresnel() {
        let (l, r) = (150.0, 400.0);
        let al = Alignment::build(&[one(SegmentKind::Clothoid, l, (0.0, 1.0 / r))], 1.5, None);
        let a = (r * l).sqrt();
        let scale = a * std::f64::consts::PI.sqrt();
        for &u in &[3.3, 47.0, 99.99, 150.0] {
            let f = al.frame_at(u);
            let (c, s) = crate::math::fresnel(u / scale).unwrap();
            assert!((f.position_g[0] - scale * c).abs() < 1e-10, "u={u}");
            assert!((f.position_g[1] - scale * s).abs() < 1e-10, "u={u}");
        }
    }
}
