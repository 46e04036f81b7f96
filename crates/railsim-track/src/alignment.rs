//! Compiled alignment: plan geometry (tangent, transition curve, circular arc), cant and
//! gradient, and its evaluation s → [`TrackFrame`].
//!
//! Plan geometry. Along each segment the curvature is κ(u) = κ₀ + Δκ f(u/L) with a shape f
//! rising from f(0) = 0 to f(1) = 1 ([`TransitionShape`]; f = 0 on tangents and arcs), so the
//! heading is ψ(u) = ψ₀ + κ₀ u + Δκ L F(u/L) with F = ∫₀ᵗ f, and the position is
//! x(u) = x₀ + ∫₀ᵘ cos ψ, y(u) = y₀ + ∫₀ᵘ sin ψ. Tangents and arcs use the closed form
//! (chord of length 2 sin(κu/2)/κ along ψ₀ + κu/2). A clothoid (f = t) is the Euler spiral
//! whose coordinates are Fresnel integrals (Abramowitz & Stegun 7.3; for a spiral from κ = 0,
//! x = a√π C(u/(a√π)), y = a√π S(u/(a√π)) with a² = 1/κ′). Every transition is integrated with
//! 8-point Gauss–Legendre quadrature from knots precomputed at compile time every ≤ 10 m, which
//! agrees with the Fresnel form to about 1e-12 m (see the tests), works between any two
//! curvatures and costs one fixed-size quadrature per lookup.

use crate::math::{GL8_W, GL8_X};

/// \[m\] longest distance integrated by quadrature in one lookup (knot spacing on transitions).
const KNOT_SPACING_M: f64 = 10.0;

/// Kind of an alignment segment.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SegmentKind {
    /// Straight line: zero curvature, constant cant (normally zero).
    Tangent,
    /// Transition curve: curvature and cant go from the previous segment's to the next one's
    /// along the shape.
    Transition(TransitionShape),
    /// Circular curve: constant curvature and cant.
    Curve,
}

impl SegmentKind {
    /// The name in a track file (`type = ...`).
    pub fn name(self) -> &'static str {
        match self {
            SegmentKind::Tangent => "tangent",
            SegmentKind::Transition(shape) => shape.name(),
            SegmentKind::Curve => "curve",
        }
    }
}

/// How curvature and cant change along a transition curve: κ = κ₀ + Δκ f(t) and
/// cant = c₀ + Δc f(t) with t = u/L. Every shape has f(0) = 0, f(1) = 1 and ∫₀¹ f = 1/2, so all
/// turn the track by the same angle (κ₀ + κ₁) L/2.
///
/// Sources: the clothoid is the standard railway transition (Esveld, *Modern Railway Track*,
/// 2nd ed. 2001, alignment chapter, unverified here); the Bloss curve f = 3t² − 2t³ (Bloss,
/// 1936) and the cosine (half-wave sine) curve f = (1 − cos πt)/2 have zero curvature rate and
/// cant slope at both ends. The shift of the circle from the tangent, p ≈ L²/(24R) for the
/// clothoid and L²/(40R) for Bloss, follows from y(L) = ∫₀ᴸ (L − v) κ(v) dv and is checked in
/// the tests, with a Bloss end point quoted from a track-design program
/// (`docs/models/track.md`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TransitionShape {
    /// f = t: curvature and cant linear in s (the Euler spiral).
    Clothoid,
    /// f = 3t² − 2t³.
    Bloss,
    /// f = (1 − cos πt)/2.
    Cosine,
}

impl TransitionShape {
    /// Every shape, in the order of the file format's documentation.
    pub const ALL: [TransitionShape; 3] = [
        TransitionShape::Clothoid,
        TransitionShape::Bloss,
        TransitionShape::Cosine,
    ];

    /// The name in a track file (`type = ...`).
    pub fn name(self) -> &'static str {
        match self {
            TransitionShape::Clothoid => "clothoid",
            TransitionShape::Bloss => "bloss",
            TransitionShape::Cosine => "cosine",
        }
    }

    /// f(t), f'(t), f''(t) and F(t) = ∫₀ᵗ f for t in \[0, 1\].
    #[inline]
    pub fn eval(self, t: f64) -> ShapeValues {
        match self {
            TransitionShape::Clothoid => ShapeValues {
                f: t,
                df: 1.0,
                d2f: 0.0,
                integral: 0.5 * t * t,
            },
            TransitionShape::Bloss => ShapeValues {
                f: t * t * (3.0 - 2.0 * t),
                df: 6.0 * t * (1.0 - t),
                d2f: 6.0 - 12.0 * t,
                integral: t * t * t * (1.0 - 0.5 * t),
            },
            TransitionShape::Cosine => {
                let (s, c) = (std::f64::consts::PI * t).sin_cos();
                let pi = std::f64::consts::PI;
                ShapeValues {
                    f: 0.5 * (1.0 - c),
                    df: 0.5 * pi * s,
                    d2f: 0.5 * pi * pi * c,
                    integral: 0.5 * t - s / (2.0 * pi),
                }
            }
        }
    }
}

/// A transition shape's values at one t ([`TransitionShape::eval`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShapeValues {
    /// f(t)
    pub f: f64,
    /// f'(t)
    pub df: f64,
    /// f''(t)
    pub d2f: f64,
    /// ∫₀ᵗ f
    pub integral: f64,
}

/// Index of a segment in [`crate::TrackModel::segments`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct SegmentId(pub usize);

/// A compiled segment: everything in SI, start state precomputed.
#[derive(Debug, Clone, PartialEq)]
pub struct Segment {
    /// Tangent, transition or curve.
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
    /// First knot in [`Alignment::knots`] and knot spacing \[m\] (transitions only).
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
    /// \[1/m²\] dκ/ds (non-zero on transitions).
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
    /// \[rad/m²\] d²φ/ds² (non-zero inside Bloss and cosine transitions).
    pub droll_ds2: f64,
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

/// Integrate (cos ψ, sin ψ) for ψ(v) = `psi(v)` over v ∈ \[0, d\] with 8-point
/// Gauss–Legendre.
#[inline]
fn quad_delta(psi: impl Fn(f64) -> f64, d: f64) -> (f64, f64) {
    let h = 0.5 * d;
    let (mut cx, mut cy) = (0.0, 0.0);
    for j in 0..4 {
        for sgn in [-1.0, 1.0] {
            let (s, c) = psi(h + sgn * GL8_X[j] * h).sin_cos();
            cx += GL8_W[j] * c;
            cy += GL8_W[j] * s;
        }
    }
    (cx * h, cy * h)
}

/// The heading change ψ(u) − ψ₀ of a transition of `length` from curvature `k0` to `k1`.
#[inline]
fn transition_turn(shape: TransitionShape, k0: f64, k1: f64, length: f64, u: f64) -> f64 {
    k0 * u + (k1 - k0) * length * shape.eval(u / length).integral
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
            let knot_first = knots.len();
            let mut knot_spacing = 0.0;
            if let SegmentKind::Transition(shape) = inp.kind {
                let l = inp.length;
                let n = (l / KNOT_SPACING_M).ceil().max(1.0) as usize;
                knot_spacing = l / n as f64;
                let (mut kx, mut ky, mut kpsi) = (x, y, psi);
                for i in 0..=n {
                    knots.push(Knot {
                        x: kx,
                        y: ky,
                        psi: kpsi,
                    });
                    if i < n {
                        let u = i as f64 * knot_spacing;
                        let turn = |v: f64| psi + transition_turn(shape, k0, k1, l, u + v);
                        let (dx, dy) = quad_delta(turn, knot_spacing);
                        kx += dx;
                        ky += dy;
                        kpsi = turn(knot_spacing);
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
        let SegmentKind::Transition(shape) = seg.kind else {
            return arc(seg.x_start, seg.y_start, seg.heading_start, k0, u);
        };
        let (k1, l) = (seg.curvature_end, seg.length);
        let n_knots = (l / seg.knot_spacing).round() as usize;
        let i = ((u / seg.knot_spacing) as usize).min(n_knots.saturating_sub(1));
        let knot = self.knots[seg.knot_first + i];
        let ui = i as f64 * seg.knot_spacing;
        let turn = |v: f64| seg.heading_start + transition_turn(shape, k0, k1, l, v);
        let (dx, dy) = quad_delta(|v| turn(ui + v), u - ui);
        (knot.x + dx, knot.y + dy, turn(u))
    }

    /// The track frame at s. Outside \[0, length\] the track continues with the end's curvature,
    /// cant and gradient.
    pub(crate) fn frame_at(&self, s: f64) -> TrackFrame {
        let seg = &self.segments[self.segment_index(s)];
        let u_raw = s - seg.s_start;
        let u = u_raw.clamp(0.0, seg.length);
        let outside = u_raw - u;
        let inv_l = 1.0 / seg.length;
        let (mut x, mut y, mut psi) = self.plan_at(seg, u);
        // the shape's f, f', f'' (a tangent or an arc: constant)
        let sh = match seg.kind {
            SegmentKind::Transition(shape) => shape.eval(u * inv_l),
            _ => ShapeValues {
                f: 0.0,
                df: 0.0,
                d2f: 0.0,
                integral: 0.0,
            },
        };
        let (dk, dc) = (
            seg.curvature_end - seg.curvature_start,
            seg.cant_end - seg.cant_start,
        );
        let mut kappa = seg.curvature_start + dk * sh.f;
        let mut dkappa = dk * sh.df * inv_l;
        let mut cant = seg.cant_start + dc * sh.f;
        let mut dcant = dc * sh.df * inv_l;
        let mut d2cant = dc * sh.d2f * inv_l * inv_l;
        if outside != 0.0 {
            (x, y, psi) = arc(x, y, psi, kappa, outside);
            dkappa = 0.0;
            dcant = 0.0;
            d2cant = 0.0;
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
        // d/ds of c'/(b cos φ)
        let d2roll = d2cant / (self.cant_base * roll.cos()) + roll.tan() * droll * droll;
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
            droll_ds2: d2roll,
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
        let al = Alignment::build(
            &[one(
                SegmentKind::Transition(TransitionShape::Clothoid),
                l,
                (0.0, 1.0 / r),
            )],
            1.5,
            None,
        );
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
