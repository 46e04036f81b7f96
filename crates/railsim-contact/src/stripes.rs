//! STRIPES, the semi-Hertzian normal model of Ayasse & Chollet (VSD 43, 2005) on the isosceles
//! strips of Jalili & Salehi (2011, §3.4), with FaStrip or FASTSIM per strip for the tangential
//! problem.
//!
//! Per patch, with the rigid pair's curvatures `A0`, `B0` and Hertz coefficients `m0, n0, r0`:
//! - `eps0 = n0^2 B0 / (r0 (A0 + B0))` (seed eq. 8), `h0 = eps0 delta0` (seed eq. 7);
//! - per strip `h_i = max(0, eps0 delta0 - g_i)`, where `g_i = delta0 - d_i >= 0` is the strip's
//!   gap below the deepest point. The seed prints eq. (9) as `max(0, delta0 (1 - eps0) - z_i)`,
//!   which contradicts eq. (7) at the deepest strip unless eps0 = 1/2 (contact-theory.md §2.1).
//!   We implement the form that gives `h_i0 = eps0 delta0`, the only one consistent with eq. (7);
//!   a test shows it returns Hertz exactly for a constant-curvature geometry;
//! - `A_i^C = (n_i/m_i)^2 B_i` (seed eq. 6, applied per strip), `a_i = sqrt(h_i / A_i^C)` (eq. 10);
//! - line load `q_i = E/(2(1-nu^2)) h_i / (n_i r_i eps_i)` (eq. 14 per unit width; for two equal
//!   materials E/(1-nu^2) = 2 E*), pressure semi-elliptic in x with peak `2 q_i / (pi a_i)`
//!   (eq. 11);
//! - the strip loads are integrated over the lateral coordinate with the trapezoidal rule, the
//!   zero crossings of `h` at the patch edges interpolated linearly.
//!
//! The isosceles strips are slightly rotated against the projected strips of the original
//! method; the seed shows the product `z_i dy_i` is unchanged to first order (eqs. 15–17). Here
//! the interpenetration is projected on the patch normal and the lateral coordinate on the patch
//! tangent, i.e. the strips are used in the original (projected) form.
//!
//! Tangential forces: FaStrip (Sichani et al. 2016, the default) or FASTSIM (Kalker 1982) per
//! strip, each strip a line of `nx` cells with its own rigid slip (the wheel's velocity at the
//! strip's locus point, which carries the spin variation across the patch), and the Kalker
//! coefficients and flexibilities of the strip's own ellipse: the Hertz ellipse of its local
//! curvatures at the patch's approach (`StripEllipse`; until this version the patch's area- and
//! aspect-preserving equivalent ellipse of Kik & Piotrowski 2008, as CONTACT does, which now
//! stands in only where the strip's ellipse is degenerate).

use railsim_elastic::{
    Creepages, FastripPatch, FlexibilityBlend, Grid, KalkerTable, SteadyRollingSolver,
    StripTraction, TractionBound, fastrip_strip, fastsim_strip, hertz_coeffs_fast, stripes_epsilon,
};

use crate::error::ContactError;
use crate::friction::FallingFriction;
use crate::geometry::{IsoPair, Zone};
use crate::model::{PatchForces, PatchInput};
use crate::patch::{B_MIN, from_plane_to_frame, longitudinal_curvature, mid};
use crate::wells::{WellScratch, memberships};

/// The tangential solution per strip.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Tangential {
    /// FASTSIM (Kalker 1982), three flexibilities of each strip's ellipse, CONTACT's blending.
    Fastsim,
    /// FaStrip (Sichani, Enblom & Berg 2016): strip theory with spin calibrated to Kalker's
    /// linear theory, FASTSIM directions in slip and FASTSIM where strip theory breaks down.
    /// Semi-elliptic pressure (the traction-bound option does not apply).
    Fastrip,
    /// Kalker's exact steady-rolling solution (the half-space tangential problem of CONTACT,
    /// [`railsim_elastic::steady`]) on a grid over the patch, with the normal pressure of the
    /// patch's normal solution and each row's own rigid slip. The reference level: about a
    /// thousand times slower than FaStrip (docs/performance.md).
    Exact,
}

/// Reusable buffers of the exact tangential solution.
#[derive(Default)]
pub struct ExactScratch {
    solver: Option<SteadyRollingSolver>,
    pn: Vec<f64>,
    wx: Vec<f64>,
    wy: Vec<f64>,
    /// \[-\] a varying friction's coefficient per grid row (cleared by `prepare`); empty for a
    /// constant one
    pub(crate) mu_row: Vec<f64>,
}

impl ExactScratch {
    /// The solver set to `grid`, reusing the buffers, and zeroed cell arrays.
    fn prepare(
        &mut self,
        grid: Grid,
        mat: &railsim_elastic::Material,
    ) -> Result<&mut SteadyRollingSolver, ContactError> {
        for v in [&mut self.pn, &mut self.wx, &mut self.wy] {
            v.clear();
            v.resize(grid.len(), 0.0);
        }
        self.mu_row.clear();
        match &mut self.solver {
            Some(s) => {
                if *s.grid() != grid {
                    s.set_grid(grid, mat)?;
                }
            }
            None => self.solver = Some(SteadyRollingSolver::new(grid, mat)?),
        }
        Ok(self.solver.as_mut().expect("solver was just set"))
    }

    /// As [`Self::prepare`], with the pressure `pn` of the grid's cells.
    pub(crate) fn prepare_with(
        &mut self,
        grid: Grid,
        mat: &railsim_elastic::Material,
        pn: &[f64],
    ) -> Result<(), ContactError> {
        self.prepare(grid, mat)?;
        self.pn.copy_from_slice(pn);
        Ok(())
    }
}

/// Convergence tolerance of the exact tangential solution (largest traction change of a sweep
/// relative to the largest traction).
pub const EXACT_TOL: f64 = 1e-7;
/// Sweep limit of the exact tangential solution.
pub const EXACT_MAX_SWEEPS: usize = 1000;

/// Kalker's exact steady-rolling solution for a patch whose normal pressure `scratch.pn` is
/// given on `grid` (x along the track, y the lateral coordinate in the patch plane, both from the
/// reference point). Sets `fx`, `fs`, `mz` (about the reference point) and the adhesion fraction.
///
/// The rigid slip is that of CONTACT's planar contact approach (D = 2, the reference's own
/// definition): one contact plane per patch, the creepages of the patch reference point (the
/// `d^(5/2)`-weighted centroid, [`crate::patch::reference_point`], with its own normal and
/// tangent), and `w = (xi - phi (y - y_c), eta + phi (x - x_c))` over the plane about that point
/// (Kalker 1990; Vollebregt, VSD 60, 2022). The returned `fx`, `fs` lie along the track and the
/// reference point's tangent. Until stop 34 the creepages and origin were the rigid pair's: on
/// the 14 mm wide conformal patch of the benchmark (right wheel, y = 0.5 mm) the two points'
/// spins differ by 16 % (docs/models/contact.md §6). The per-strip FASTSIM/FaStrip levels use
/// each strip's own creepages instead.
pub(crate) fn solve_exact(
    input: &PatchInput<'_>,
    grid: Grid,
    scratch: &mut ExactScratch,
    f: &mut PatchForces,
) -> Result<(), ContactError> {
    let (nx, ny) = (grid.nx, grid.ny);
    let (c, dx, dl) = planar_creepages(input);
    for iy in 0..ny {
        for ix in 0..nx {
            let k = ix + nx * iy;
            scratch.wx[k] = c.xi - c.phi * (grid.y(iy) - dl);
            scratch.wy[k] = c.eta + c.phi * (grid.x(ix) - dx);
        }
    }
    let ExactScratch {
        solver,
        pn,
        wx,
        wy,
        mu_row,
    } = scratch;
    // The tangential problem sees the pressure only through the traction bound μ·p (and where
    // it is positive): a varying friction enters as the rows' pressures scaled by their μ, with
    // μ = 1 for the solver.
    let mu = if mu_row.len() == ny {
        for (iy, m) in mu_row.iter().enumerate() {
            for v in &mut pn[nx * iy..nx * (iy + 1)] {
                *v *= m;
            }
        }
        1.0
    } else {
        input.pair.friction.max()
    };
    let solver = solver.as_mut().expect("prepared");
    let sol = solver.solve(pn, wx, wy, mu, EXACT_TOL, EXACT_MAX_SWEEPS, false)?;
    f.fx = sol.fx;
    f.fs = sol.fy;
    f.mz = sol.mz;
    f.adhesion_fraction = if sol.n_contact > 0 {
        sol.n_adhesion as f64 / sol.n_contact as f64
    } else {
        0.0
    };
    Ok(())
}

/// The planar rigid slip's creepages and origin ([`solve_exact`]): those of the patch reference
/// point, taken with its own normal and tangent, and its offset `(dx, dl)` along the track and
/// along the frame tangent from the rigid pair, the origin of the grids.
fn planar_creepages(input: &PatchInput<'_>) -> (Creepages, f64, f64) {
    let fr = &input.frame;
    let (rp, angle) = input.reference;
    let (sa, ca) = angle.sin_cos();
    let creep = input
        .kin
        .creepages([rp.x, rp.a[0], rp.a[1]], [ca, sa], [-sa, ca]);
    let dl = (rp.b[0] - fr.rail_point[0]) * fr.t[0] + (rp.b[1] - fr.rail_point[1]) * fr.t[1];
    (creep, rp.x - fr.wheel_point[0], dl)
}

/// Mean of `sqrt(1 - t^2)` (zero outside [-1, 1]) over `[t1, t2]`, times `t2 - t1`: the exact
/// integral of the unit semi-ellipse over a cell.
fn semi_ellipse_integral(t1: f64, t2: f64) -> f64 {
    let prim = |t: f64| {
        let t = t.clamp(-1.0, 1.0);
        0.5 * (t * (1.0 - t * t).max(0.0).sqrt() + t.asin())
    };
    prim(t2) - prim(t1)
}

/// The exact tangential solution on the STRIPES pressure: the strips' semi-elliptic pressures
/// interpolated linearly in the lateral coordinate onto `cells` rows (line load and half-length
/// tapering to zero at the patch edges `l_min`, `l_max`), integrated exactly over each cell, and
/// scaled to the patch's normal force.
#[allow(clippy::too_many_arguments)]
fn exact_on_strips(
    input: &PatchInput<'_>,
    strips: &[Strip],
    l_min: f64,
    l_max: f64,
    cells: (usize, usize),
    scratch: &mut ExactScratch,
    f: &mut PatchForces,
) -> Result<(), ContactError> {
    let n = strips.len();
    let asc = strips[n - 1].l >= strips[0].l;
    let at = |k: usize| -> &Strip { if asc { &strips[k] } else { &strips[n - 1 - k] } };
    let mut x_lo = f64::INFINITY;
    let mut x_hi = f64::NEG_INFINITY;
    for s in strips {
        x_lo = x_lo.min(s.x - s.a);
        x_hi = x_hi.max(s.x + s.a);
    }
    let margin = 0.02 * (x_hi - x_lo);
    let (nx, ny) = cells;
    let grid = Grid::covering(nx, ny, x_lo - margin, x_hi + margin, l_min, l_max)?;
    scratch.prepare(grid, &input.pair.material)?;
    // Row profile at lateral coordinate l: (line load, half-length, centre x).
    let row = |l: f64| -> (f64, f64, f64) {
        let first = at(0);
        let last = at(n - 1);
        if l <= first.l {
            let r = ((l - l_min) / (first.l - l_min)).clamp(0.0, 1.0);
            return (first.q * r, first.a * r.sqrt(), first.x);
        }
        if l >= last.l {
            let r = ((l_max - l) / (l_max - last.l)).clamp(0.0, 1.0);
            return (last.q * r, last.a * r.sqrt(), last.x);
        }
        let mut k = 0;
        while k + 2 < n && at(k + 1).l < l {
            k += 1;
        }
        let (s0, s1) = (at(k), at(k + 1));
        let t = (l - s0.l) / (s1.l - s0.l);
        let lerp = |a: f64, b: f64| a + t * (b - a);
        (lerp(s0.q, s1.q), lerp(s0.a, s1.a), lerp(s0.x, s1.x))
    };
    let mut total = 0.0;
    for iy in 0..ny {
        let (q, a, xc) = row(grid.y(iy));
        if q <= 0.0 || a <= 0.0 {
            continue;
        }
        // line load q over [xc - a, xc + a] as a semi-ellipse: p = (2 q / (pi a)) sqrt(1 - t^2)
        let p0 = 2.0 * q / (std::f64::consts::PI * a);
        for ix in 0..nx {
            let x = grid.x(ix);
            let t1 = (x - 0.5 * grid.dx - xc) / a;
            let t2 = (x + 0.5 * grid.dx - xc) / a;
            let v = p0 * a * semi_ellipse_integral(t1, t2) / grid.dx;
            scratch.pn[ix + nx * iy] = v;
            total += v;
        }
    }
    let total = total * grid.cell_area();
    if total <= 0.0 {
        return Ok(());
    }
    let scale = f.fn_ / total;
    for v in scratch.pn.iter_mut() {
        *v *= scale;
    }
    if !input.pair.friction.is_constant() {
        // each row's coefficient: that of the strip nearest to it
        for iy in 0..ny {
            let l = grid.y(iy);
            let near = strips
                .iter()
                .min_by(|a, b| (a.l - l).abs().total_cmp(&(b.l - l).abs()))
                .expect("strips is not empty");
            let n = input.pairs[near.pair].n;
            scratch.mu_row.push(input.pair.friction.at_normal(n));
        }
    }
    solve_exact(input, grid, scratch, f)
}

/// Which virtual-penetration ratio bounds the strips.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum StripesVariant {
    /// The seed's eq. (9) (with the sign of eq. 7): one ratio eps0, from the rigid pair's
    /// curvatures, for every strip: `h_i = eps0 delta0 - g_i`.
    Seed,
    /// Each strip's own ratio from its local curvatures: `h_i = eps_i delta0 - g_i`. Identical to
    /// `Seed` where the curvatures are constant (so still exact for Hertz), but wide, flat
    /// (conformal) shoulders of a patch are no longer under-loaded. The same idea as the local
    /// correction factors of ANALYN (Sichani, Enblom & Berg, VSD 52, 2014). Default: on the
    /// Manchester benchmark it cuts the penetration error at y = 0.5 mm (right) from 42 % to
    /// 6 % (docs/validation.md).
    LocalEpsilon,
}

/// Per-pair scratch of a STRIPES solve.
#[derive(Clone, Copy, Debug)]
pub struct Local {
    u: f64,
    /// \[-\] membership in the patch's well (`memberships`)
    chi: f64,
    l: f64,
    b: f64,
    hc: railsim_elastic::HertzCoeffs,
    /// \[Pa\] line load per unit virtual interpenetration, E*/(n r eps)
    k: f64,
    load: f64,
    width: f64,
    /// \[m\] interpenetration along the pair's normal
    d: f64,
    /// \[1/m\] longitudinal relative curvature A_i
    a_long: f64,
    /// \[m\] arc lengths of the pair's rail and wheel points
    s_r: f64,
    s_w: f64,
    /// \[1/m\] `relative_curvature` at the pair (NaN until a junction segment needs it)
    b_exact: f64,
    /// (q, u) at the pair with `b_exact` (`line_load`)
    qu_exact: (f64, f64),
}

/// \[Pa\] peak of the pressure along a strip of half-length `a` that carries the line load `q`:
/// `2q/(pi a)` for a semi-ellipse, `3q/(4a)` for a parabola.
pub fn peak_for_line_load(q: f64, a: f64, bound: TractionBound) -> f64 {
    match bound {
        TractionBound::Elliptic => 2.0 * q / (std::f64::consts::PI * a),
        TractionBound::Parabolic => 0.75 * q / a,
    }
}

/// Parabola through three (l, u) points, evaluated at `l`.
#[inline]
fn quad(a: &Local, b: &Local, c: &Local, l: f64) -> f64 {
    let (x0, x1, x2) = (a.l, b.l, c.l);
    a.u * (l - x1) * (l - x2) / ((x0 - x1) * (x0 - x2))
        + b.u * (l - x0) * (l - x2) / ((x1 - x0) * (x1 - x2))
        + c.u * (l - x0) * (l - x1) / ((x2 - x0) * (x2 - x1))
}

/// \[-\] ln of the ratio of the line-load coefficients K at the two ends of a segment from
/// which its load is also integrated at sub-points (`junction_segment`)...
const JUNCTION_FROM: f64 = 0.1;
/// \[-\] ... and from which that integral is taken alone.
const JUNCTION_FULL: f64 = 0.3;
/// Sub-intervals of a junction segment.
const JSUB: usize = 4;

/// \[-\] How much of a segment's load comes from the integration at sub-points: 0 where the
/// line-load coefficients `k0`, `k1` (K = E*/(n r eps), which follows the relative curvature)
/// at its ends differ by less than a factor e^JUNCTION_FROM, 1 from e^JUNCTION_FULL on, a C1
/// smoothstep in ln(k1/k0) between.
#[inline]
fn junction_weight(k0: f64, k1: f64) -> f64 {
    let v = (k1 / k0).ln().abs();
    let t = ((v - JUNCTION_FROM) / (JUNCTION_FULL - JUNCTION_FROM)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// \[1/m\] the relative lateral curvature B = (κ_w − κ_r)/2, unclamped, at the wheel and rail
/// arc lengths `s_w`, `s_r`; with yaw the locus' own curvature at a fixed difference step
/// (`locus_curvature`), not the pairs' central difference, which spreads a change of the
/// locus' curvature over the pairs' spacing. (Interpolating the yaw's part of it between the
/// pairs instead saved 3 % of the contact cost on the rigid R = 150 m curve and moved the flange
/// patch's forces by up to 0.1 %: not kept.)
fn relative_curvature(input: &PatchInput<'_>, s_w: f64, s_r: f64) -> f64 {
    let pair = input.pair;
    let kw = if input.ctx.yawed {
        crate::geometry::locus_curvature(pair, &input.ctx, s_w)
    } else {
        pair.wheel.curvature(s_w)
    };
    0.5 * (kw - pair.rail.curvature(s_r))
}

/// The patch's constants of a strip's line load: the variant, ε0, δ0 \[m\] and E* \[Pa\].
struct StripLaw {
    variant: StripesVariant,
    eps0: f64,
    delta0: f64,
    e_star: f64,
}

/// A strip with curvatures `a_i`, `b_i` (clamped to `B_MIN`) and interpenetration `d` \[m\]:
/// its Hertz coefficients, its virtual interpenetration u = d − (1 − ε)δ0 and its line-load
/// coefficient K = E*/(n r ε_i) \[Pa\] (seed eq. 8 and 14 per strip; ε is ε_i or the patch's
/// ε0 by the variant).
#[inline]
fn strip_law(
    a_i: f64,
    b_i: f64,
    d: f64,
    law: &StripLaw,
) -> (railsim_elastic::HertzCoeffs, f64, f64) {
    let hc = hertz_coeffs_fast(a_i, b_i);
    let eps_i = stripes_epsilon(&hc, a_i, b_i);
    let eps = match law.variant {
        StripesVariant::Seed => law.eps0,
        StripesVariant::LocalEpsilon => eps_i,
    };
    let u = d - (1.0 - eps) * law.delta0;
    (hc, u, law.e_star / (hc.n * hc.r * eps_i))
}

/// (q, u) of a strip with curvatures `a_i`, `b` (unclamped) and interpenetration `d` \[m\]:
/// its line load q = K max(u, 0) and virtual interpenetration u ([`strip_law`]).
#[inline]
fn line_load(a_i: f64, b: f64, d: f64, law: &StripLaw) -> (f64, f64) {
    let (_, u, k) = strip_law(a_i, b.max(B_MIN), d, law);
    (k * u.max(0.0), u)
}

/// (load, width) of pair `p0` and of pair `p1` from the segment between them, integrated on
/// [`JSUB`] sub-intervals with the relative curvature B taken at each sub-point from the
/// profiles at the arc lengths interpolated linearly between the pairs (`relative_curvature`),
/// so that a steep change of the curvature inside the segment is placed where the profiles have
/// it. The interpenetration follows the same curvature: d'' = −2B along the patch (the gap's
/// second derivative is twice the relative curvature, Hertz's quadratic gap), integrated twice on
/// the sub-intervals, plus the linear function that meets the pairs' own d at both ends; the mean
/// of two parabolas through the pairs (the plain sub-intervals) misses d'' where it changes
/// inside the segment. The line load per sub-point is [`line_load`]; the ends' are kept with the
/// pairs.
fn junction_segment(p0: &Local, p1: &Local, input: &PatchInput<'_>, law: &StripLaw) -> [f64; 4] {
    let h = (p1.l - p0.l) / JSUB as f64;
    // the relative curvature (unclamped) at the sub-points, the ends' kept with the pairs
    let mut b = [0.0; JSUB + 1];
    b[0] = p0.b_exact;
    b[JSUB] = p1.b_exact;
    for (j, bj) in b.iter_mut().enumerate().take(JSUB).skip(1) {
        let t = j as f64 / JSUB as f64;
        *bj = relative_curvature(
            input,
            p0.s_w + t * (p1.s_w - p0.s_w),
            p0.s_r + t * (p1.s_r - p0.s_r),
        );
    }
    // d'' = -2B twice integrated from p0 (value and slope 0 there), then the linear part
    let mut d = [0.0; JSUB + 1];
    let mut slope = 0.0;
    for j in 1..=JSUB {
        let next = slope - (b[j - 1] + b[j]) * h;
        d[j] = d[j - 1] + 0.5 * (slope + next) * h;
        slope = next;
    }
    let end = d[JSUB];
    for (j, dj) in d.iter_mut().enumerate() {
        let t = j as f64 / JSUB as f64;
        *dj += p0.d + t * (p1.d - p0.d - end);
    }
    // (q = K u, u) at the sub-points
    let at = |j: usize| -> (f64, f64) {
        if j == 0 {
            return p0.qu_exact;
        }
        if j == JSUB {
            return p1.qu_exact;
        }
        let t = j as f64 / JSUB as f64;
        let a_i = p0.a_long + t * (p1.a_long - p0.a_long);
        line_load(a_i, b[j], d[j], law)
    };
    let mut out = [0.0; 4];
    let dl = h.abs();
    let (mut qa, mut ua) = at(0);
    for j in 1..=JSUB {
        let t = j as f64 / JSUB as f64;
        let (qb, ub) = at(j);
        // the positive part of u, the line load linear between the ends and the zero crossing
        let (len, mean_q, mid_t) = if ua > 0.0 && ub > 0.0 {
            (dl, 0.5 * (qa + qb), t - 0.5 / JSUB as f64)
        } else if ua > 0.0 {
            let f = ua / (ua - ub);
            (dl * f, 0.5 * qa, t - (1.0 - 0.5 * f) / JSUB as f64)
        } else if ub > 0.0 {
            let f = ub / (ub - ua);
            (dl * f, 0.5 * qb, t - 0.5 * f / JSUB as f64)
        } else {
            (0.0, 0.0, 0.0)
        };
        if len > 0.0 {
            let part = len * (p0.chi + mid_t * (p1.chi - p0.chi));
            let target = if mid_t < 0.5 { 0 } else { 2 };
            out[target] += mean_q * part;
            out[target + 1] += part;
        }
        (qa, ua) = (qb, ub);
    }
    out
}

/// One strip of a STRIPES patch.
#[derive(Clone, Copy, Debug, Default)]
pub struct Strip {
    /// \[m\] lateral coordinate in the patch plane, from the reference point
    pub l: f64,
    /// \[m\] width carried by the strip
    pub w: f64,
    /// \[m\] virtual interpenetration h_i
    pub h: f64,
    /// \[N/m\] line load
    pub q: f64,
    /// \[m\] half-length
    pub a: f64,
    /// \[m\] longitudinal position of the strip centre relative to the reference point
    pub x: f64,
    /// index of the isosceles pair
    pub pair: usize,
    /// \[-\] membership of the strip in the patch's well (1 inside its basin), the part of
    /// its width `w` already counts
    pub chi: f64,
}

/// Normal and tangential solution of one patch with STRIPES + FASTSIM per strip; `falling`
/// lowers each strip's friction with its rigid slip velocity (FaStrip and FASTSIM only; the
/// caller refuses it with the exact solution).
#[allow(clippy::too_many_arguments)]
pub fn solve(
    input: &PatchInput<'_>,
    variant: StripesVariant,
    tangential: Tangential,
    falling: &FallingFriction,
    nx: usize,
    bound: TractionBound,
    exact_cells: (usize, usize),
    strips: &mut Vec<Strip>,
    local: &mut Vec<Local>,
    exact: &mut ExactScratch,
    wells: &mut WellScratch,
) -> Result<PatchForces, ContactError> {
    let fr = &input.frame;
    let pairs = input.pairs;
    let mat = input.pair.material;
    let e_star = mat.e_star();
    let hc0 = hertz_coeffs_fast(fr.a_curv, fr.b_curv);
    let eps0 = stripes_epsilon(&hc0, fr.a_curv, fr.b_curv);
    let delta0 = fr.delta0;
    let law = StripLaw {
        variant,
        eps0,
        delta0,
        e_star,
    };
    // The patch is a well of its run (`crate::wells`): its strips are the run's, each weighted by
    // its membership in the well, and the patch carries the well's share (applied by the caller).
    let (lo, hi) = run_range(pairs, input.zone);
    // Per pair: local curvatures and Hertz coefficients, the interpenetration along the pair's
    // own normal, the lateral coordinate as arc length along the patch (the chain of pair
    // midpoints), and u = virtual interpenetration (positive inside). Measuring along each
    // strip's normal and along the curved patch keeps the solution independent of which pair the
    // frame sits at: a wide flange-root zone turns through half a radian, and projecting on the
    // frame's plane made the vertical load jump by 39 % when its deepest pair moved from one end
    // to the other (docs/models/contact.md §5).
    local.clear();
    let mut arc = 0.0;
    for i in lo..=hi {
        if i > lo {
            let (m0, m1) = (mid(&pairs[i - 1]), mid(&pairs[i]));
            let (dy, dz) = (m1[0] - m0[0], m1[1] - m0[1]);
            let step = (dy * dy + dz * dz).sqrt();
            arc += if dy * fr.t[0] + dz * fr.t[1] >= 0.0 {
                step
            } else {
                -step
            };
        }
        let p = &pairs[i];
        let a_i = longitudinal_curvature(p.rho, p.rho_slope);
        let kw = crate::geometry::locus_curvature_at(pairs, i, input.ctx.yawed);
        let b_i = (0.5 * (kw - p.kappa_r)).max(B_MIN);
        let d = -p.gap;
        let (hc, u, k) = strip_law(a_i, b_i, d, &law);
        local.push(Local {
            u,
            chi: 1.0,
            l: arc,
            b: b_i,
            hc,
            k,
            load: 0.0,
            width: 0.0,
            d,
            a_long: a_i,
            s_r: p.s_r,
            s_w: p.s_w,
            b_exact: f64::NAN,
            qu_exact: (0.0, 0.0),
        });
    }
    let chi = memberships(pairs, input.zone.deepest, lo, local.len(), wells);
    for (li, c) in local.iter_mut().zip(chi) {
        li.chi = *c;
    }
    // The arc-length coordinate from the frame's point (the deepest pair's lateral position in
    // the frame, where the two coordinates agree to second order).
    let deep = fr.deepest.clamp(lo, hi);
    let shift = fr.lateral(&pairs[deep]) - local[deep - lo].l;
    for li in local.iter_mut() {
        li.l += shift;
    }
    // Lateral integration of the line load q = K u, K = E*/(n r eps): on each segment between
    // two pairs, u is interpolated by the mean of the two parabolas through the neighbouring
    // pairs (third-order accurate; linear where a neighbour is missing), the positive part is
    // integrated on SUB sub-intervals, and the load and width go to the nearer pair.
    // Where the relative curvature B changes steeply between the two pairs (a junction of the
    // profiles' arcs, where K and eps change by up to 30 times within a tenth of a millimetre),
    // that interpolation does not see where the change lies, and the load converged only to
    // first order in the step (docs/models/contact.md §5). There the segment is also integrated
    // on JSUB sub-intervals with the profiles' own curvatures at each sub-point, and the two are
    // blended by the size of the change (`junction_weight`), so that the load stays continuous.
    const SUB: usize = 4;
    for li in local.iter_mut() {
        li.load = 0.0;
        li.width = 0.0;
    }
    let n_loc = local.len();
    let mut l_min = f64::INFINITY;
    let mut l_max = f64::NEG_INFINITY;
    for k in 0..n_loc.saturating_sub(1) {
        if (local[k + 1].l - local[k].l).abs() < 1e-12 {
            // coincident pairs carry no width
            continue;
        }
        if local[k].u <= 0.0
            && local[k + 1].u <= 0.0
            && (k == 0 || local[k - 1].u <= 0.0)
            && (k + 2 >= n_loc || local[k + 2].u <= 0.0)
        {
            continue;
        }
        let junction = junction_weight(local[k].k, local[k + 1].k);
        if junction > 0.0 {
            // the ends' curvatures, computed once per pair
            for li in &mut local[k..=k + 1] {
                if li.b_exact.is_nan() {
                    li.b_exact = relative_curvature(input, li.s_w, li.s_r);
                    li.qu_exact = line_load(li.a_long, li.b_exact, li.d, &law);
                }
            }
        }
        let (p0, p1) = (&local[k], &local[k + 1]);
        let prev = if k > 0 { Some(&local[k - 1]) } else { None };
        let next = local.get(k + 2);
        let interp = |l: f64| -> f64 {
            let lin = p0.u + (p1.u - p0.u) * (l - p0.l) / (p1.l - p0.l);
            let mut sum = 0.0;
            let mut cnt = 0.0;
            if let Some(pm) = prev {
                sum += quad(pm, p0, p1, l);
                cnt += 1.0;
            }
            if let Some(pn) = next {
                sum += quad(p0, p1, pn, l);
                cnt += 1.0;
            }
            if cnt > 0.0 { sum / cnt } else { lin }
        };
        // (load, width) for pair k and pair k + 1, plain and at the sub-points
        let mut plain = [0.0; 4];
        let (k0, k1) = (p0.k, p1.k);
        let (c0, c1) = (p0.chi, p1.chi);
        let mut ua = p0.u;
        let mut la = p0.l;
        for j in 1..=SUB {
            let t = j as f64 / SUB as f64;
            let lb = p0.l + t * (p1.l - p0.l);
            let ub = if j == SUB { p1.u } else { interp(lb) };
            let dl = (lb - la).abs();
            // positive part of the linear piece between (la, ua) and (lb, ub)
            let (len, mean_u, mid_t) = if ua > 0.0 && ub > 0.0 {
                (dl, 0.5 * (ua + ub), t - 0.5 / SUB as f64)
            } else if ua > 0.0 {
                let f = ua / (ua - ub);
                let edge = la + f * (lb - la);
                l_min = l_min.min(edge);
                l_max = l_max.max(edge);
                (dl * f, 0.5 * ua, t - (1.0 - 0.5 * f) / SUB as f64)
            } else if ub > 0.0 {
                let f = ub / (ub - ua);
                let edge = lb - f * (lb - la);
                l_min = l_min.min(edge);
                l_max = l_max.max(edge);
                (dl * f, 0.5 * ub, t - 0.5 * f / SUB as f64)
            } else {
                (0.0, 0.0, 0.0)
            };
            if len > 0.0 {
                if ua > 0.0 && ub > 0.0 {
                    l_min = l_min.min(la.min(lb));
                    l_max = l_max.max(la.max(lb));
                }
                let kk = k0 + mid_t * (k1 - k0);
                // a strip belonging partly to the well counts with part of its width
                let part = len * (c0 + mid_t * (c1 - c0));
                let target = if mid_t < 0.5 { 0 } else { 2 };
                plain[target] += kk * mean_u * part;
                plain[target + 1] += part;
            }
            ua = ub;
            la = lb;
        }
        let add = if junction > 0.0 {
            let sub = junction_segment(p0, p1, input, &law);
            let mut add = [0.0; 4];
            for (a, (p, s)) in add.iter_mut().zip(plain.iter().zip(&sub)) {
                *a = p + junction * (s - p);
            }
            add
        } else {
            plain
        };
        local[k].load += add[0];
        local[k].width += add[1];
        local[k + 1].load += add[2];
        local[k + 1].width += add[3];
    }
    strips.clear();
    // the longest strip, its half-length weighted by its membership (continuous as a strip
    // leaves the well)
    let mut a_max: f64 = 0.0;
    for i in lo..=hi {
        let li = &local[i - lo];
        if li.load <= 0.0 || li.width <= 0.0 {
            continue;
        }
        let q = li.load / li.width;
        // virtual interpenetration consistent with the strip's mean line load
        let h = q / li.k;
        let ac = (li.hc.n / li.hc.m).powi(2) * li.b;
        let a = (h / ac).sqrt();
        a_max = a_max.max(a * li.chi);
        strips.push(Strip {
            l: li.l,
            w: li.width,
            h,
            q,
            a,
            x: pairs[i].x - fr.wheel_point[0],
            pair: i,
            chi: li.chi,
        });
    }
    if strips.is_empty() {
        return Ok(PatchForces::default());
    }
    let mut f = PatchForces::default();
    let mut area = 0.0;
    // Each strip's normal load acts along its own normal: the sum, in the frame's axes.
    let (mut load, mut load_n, mut load_t) = (0.0, 0.0, 0.0);
    for s in strips.iter() {
        let n = pairs[s.pair].n;
        let w = s.q * s.w;
        load += w;
        load_n += w * (n[0] * fr.n[0] + n[1] * fr.n[1]);
        load_t += w * (n[0] * fr.t[0] + n[1] * fr.t[1]);
        let p0 = 2.0 * s.q / (std::f64::consts::PI * s.a);
        f.p_max = f.p_max.max(p0 * s.chi);
        area += 2.0 * s.a * s.w;
    }
    // the strips' (membership-weighted) widths: the lateral extent of a connected patch
    f.width = strips.iter().map(|s| s.w).sum();
    f.length = 2.0 * a_max;
    f.area = area;
    f.n_elements = strips.len() as u32;
    if tangential == Tangential::Exact {
        // The exact tangential problem on the patch unrolled into its plane (strips at their
        // arc-length coordinates), loaded by the strips' total normal load.
        f.fn_ = load;
        exact_on_strips(input, strips, l_min, l_max, exact_cells, exact, &mut f)?;
        // the exact solution's lateral force lies along the reference point's tangent; the
        // strips' normal loads along their own normals, as with the strip solvers
        let (fn_t, fs_t) = from_plane_to_frame(0.0, f.fs, input.reference.1, fr.contact_angle);
        f.fn_ = load_n + fn_t;
        f.fs = load_t + fs_t;
        return Ok(f);
    }
    // Each strip's ellipse for its Kalker coefficients and flexibilities (`StripEllipse`): the
    // Hertz ellipse of its own curvatures at the patch's approach δ0. The patch's area- and
    // aspect-preserving equivalent ellipse (Kik & Piotrowski, CONTACT's choice) stands in where
    // that ellipse is degenerate.
    let len = f.length.max(1e-9);
    let wid = f.width.max(1e-9);
    let r = (area / std::f64::consts::PI).sqrt();
    let source = EllipseSource {
        delta0,
        equivalent: (r * (len / wid).sqrt(), r * (wid / len).sqrt(), load),
        mu: input.pair.friction.at(fr.contact_angle),
        mat: &mat,
        kalker: &input.pair.kalker,
    };
    let mut ellipse: Option<StripEllipse> = None;
    let mut n_adh = 0u32;
    let mut n_cells = 0u32;
    f.fn_ = load_n;
    f.fs = load_t;
    for s in strips.iter() {
        let p = &pairs[s.pair];
        // the strip's own lateral axis (toward the field side, like the frame's)
        let t = [p.n[1], -p.n[0]];
        let creep: Creepages = input.kin.creepages([p.x, p.a[0], p.a[1]], t, p.n);
        // the friction at the strip's normal, falling with the strip's rigid slip velocity at
        // its centre (`FallingFriction`)
        let mu0 = input.pair.friction.at_normal(p.n);
        let mu = if falling.is_coulomb() {
            mu0
        } else {
            mu0 * falling.factor(creep.xi.hypot(creep.eta) * input.kin.v_ref)
        };
        let li = &local[s.pair - lo];
        let e = source.ellipse(&mut ellipse, li.a_long, li.b, || li.hc)?;
        let st = e.solve(tangential, bound, s.l, s.w, 0.0, s.a, s.q, &creep, mu, nx);
        f.fx += st.fx;
        f.fs += st.fy * (t[0] * fr.t[0] + t[1] * fr.t[1]);
        f.fn_ += st.fy * (t[0] * fr.n[0] + t[1] * fr.n[1]);
        // the strip solved about its own centre, where its creepages are taken (solved at
        // its offset `s.x` from the reference point, the spin term phi x counted the lead twice);
        // its moment already holds the lever l of its longitudinal force
        f.mz += st.mz + s.x * st.fy;
        n_adh += st.n_adhesion;
        n_cells += st.n_cells;
    }
    f.adhesion_fraction = if n_cells > 0 {
        n_adh as f64 / n_cells as f64
    } else {
        0.0
    };
    Ok(f)
}

/// The ellipse whose Kalker coefficients and FASTSIM flexibilities a strip takes, kept for the
/// next strip of the same curvatures (a patch's strips often share them).
///
/// It is the Hertz ellipse of the strip's own relative curvatures `A_i`, `B_i` at the patch's
/// approach δ0 (the depth at which STRIPES gives the patch Hertz's solution):
/// `c = sqrt(δ0 / (r_i (A_i + B_i)))`, semi-axes `m_i c`, `n_i c` and load
/// `(4/3) E* (A_i + B_i) c³` (Johnson 1985, §4.2; the load sets the saturation creepage of the
/// flexibilities' blend). On a constant-curvature geometry every strip has the Hertz ellipse,
/// so the linear-theory calibration of FASTSIM and FaStrip holds as before. On a patch whose
/// curvature changes across it, each part takes the elasticity of its own surroundings: on the
/// benchmark's wide two-well tread patch (right wheel, y = 0.5 mm) the high-pressure well is
/// 6.7 mm long and 2.4 mm wide while the patch's equivalent ellipse is 5.2 by 9.8 mm, and with
/// that ellipse FaStrip kept up to half of each of the well's strips in adhesion where the exact
/// solution on the same pressure and slip has 86 % of the well in slip (Fs 22 % low on the well;
/// docs/models/contact.md §6, docs/validation.md §1).
#[derive(Clone, Copy, Debug)]
pub(crate) struct StripEllipse {
    /// (A_i, B_i) of the strip it was last built for
    key: (f64, f64),
    blend: FlexibilityBlend,
    patch: FastripPatch,
}

impl StripEllipse {
    /// The ellipse of a strip or grid row with longitudinal and lateral relative curvatures
    /// `a_long`, `b` \[1/m\] (`b` clamped to `B_MIN`) and their Hertz coefficients `hc`, in the
    /// patch described by `src`.
    fn new(
        a_long: f64,
        b: f64,
        hc: &railsim_elastic::HertzCoeffs,
        src: &EllipseSource<'_>,
    ) -> Result<Self, ContactError> {
        let mat = src.mat;
        let sum = a_long + b;
        let c = (src.delta0 / (hc.r * sum)).sqrt();
        let (a, b_axis, n) = if c.is_finite() && c > 0.0 {
            let n = 4.0 / 3.0 * mat.e_star() * sum * c * c * c;
            (hc.m * c, hc.n * c, n)
        } else {
            src.equivalent
        };
        let kc = src.kalker.coeffs(a, b_axis)?;
        Ok(StripEllipse {
            key: (a_long, b),
            blend: FlexibilityBlend::with_coeffs(a, b_axis, n, src.mu, mat, &kc)?,
            patch: FastripPatch {
                c11: kc.c11,
                c22: kc.c22,
                c23: kc.c23,
                a,
                b: b_axis,
                g: mat.g,
                nu: mat.nu,
            },
        })
    }

    /// The traction of one strip or grid row with this ellipse's coefficients: at lateral
    /// coordinate `l` \[m\] from the patch frame's point, `w` wide, centred at `xc` \[m\]
    /// along the rolling direction, `hl` \[m\] half long, carrying the line load `q` \[N/m\]
    /// as a semi-ellipse (FaStrip) or under `bound` (FASTSIM), with the creepages `creep` taken
    /// at its own point and friction `mu`, on `nx` cells. The flexibilities are blended with
    /// the strip's own creepages and its spin's longitudinal slip is split back (`spin_split`).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn solve(
        &self,
        tangential: Tangential,
        bound: TractionBound,
        l: f64,
        w: f64,
        xc: f64,
        hl: f64,
        q: f64,
        creep: &Creepages,
        mu: f64,
        nx: usize,
    ) -> StripTraction {
        // The creepage blend of the flexibilities (CONTACT's) is taken with each strip's own
        // creepages: with the reference point's, a wide patch's flexibilities jumped when its
        // deepest pair moved from one well to the other (with the strips solved about the
        // reference point, Fx jumped by 85 % on a flange-root zone; docs/models/contact.md §6).
        let flex = self.blend.at(creep);
        // The strip at lateral coordinate l: its longitudinal creepage ξ_i = ξ − φ l is split
        // back into the frame point's ξ and the spin's −φ l, which FASTSIM takes with L3 and
        // FaStrip with C23 (docs/models/contact.md §6).
        let c = spin_split(creep, l);
        if tangential == Tangential::Fastrip {
            let p0 = peak_for_line_load(q, hl, TractionBound::Elliptic);
            fastrip_strip(l, w, xc, hl, p0, &c, &flex, &self.patch, mu, nx).0
        } else {
            let p0 = peak_for_line_load(q, hl, bound);
            fastsim_strip(l, w, xc, hl, p0, bound, &c, &flex, mu, nx)
        }
    }
}

/// What the ellipses of one patch's strips or grid rows share ([`StripEllipse`]): the patch's
/// approach δ0 \[m\], its area- and aspect-preserving equivalent ellipse (a, b \[m\], load
/// \[N\]) that stands in where a strip's ellipse is degenerate, the friction of the flexibilities'
/// blend, the material and Kalker's table.
pub(crate) struct EllipseSource<'a> {
    pub(crate) delta0: f64,
    pub(crate) equivalent: (f64, f64, f64),
    pub(crate) mu: f64,
    pub(crate) mat: &'a railsim_elastic::Material,
    pub(crate) kalker: &'a KalkerTable,
}

impl EllipseSource<'_> {
    /// The ellipse of the strip or row with curvatures `a_long`, `b` \[1/m\] (Hertz coefficients
    /// from `hc`, asked for only when a new ellipse is built): `last` if it was built for the
    /// same curvatures (a patch's neighbouring strips often share them), otherwise a new one,
    /// kept in `last`.
    pub(crate) fn ellipse(
        &self,
        last: &mut Option<StripEllipse>,
        a_long: f64,
        b: f64,
        hc: impl FnOnce() -> railsim_elastic::HertzCoeffs,
    ) -> Result<StripEllipse, ContactError> {
        match *last {
            Some(e) if e.key == (a_long, b) => Ok(e),
            _ => {
                let e = StripEllipse::new(a_long, b, &hc(), self)?;
                *last = Some(e);
                Ok(e)
            }
        }
    }
}

/// The creepages of a strip or row at lateral coordinate `l` \[m\] from the patch frame's point
/// (the zone's rigid pair, as `Strip::l`), taken at its own point, with the spin's share of its
/// longitudinal creepage moved back to that point: `ξ = ξ_i + φ l`, so that a strip solver given
/// `y = l` forms the rigid
/// slip `ξ − φ l` with the spin's own flexibility or coefficient (FASTSIM: `ξ/L1 − φ y/L3`,
/// Kalker 1982; FaStrip: `ξ' − φ' y/a` with φ' built on C23, CONTACT's `modif_fastrip`,
/// contact-theory note §3.2–3.3). Taken whole as the strip's `ξ_i` (before stop 24), the spin's
/// longitudinal slip had the longitudinal flexibility L1 (coefficient C11).
pub(crate) fn spin_split(creep: &Creepages, l: f64) -> Creepages {
    Creepages {
        xi: creep.xi + creep.phi * l,
        ..*creep
    }
}

/// The pairs a well's STRIPES solution runs over: the interpenetrating run that holds the well
/// `zone`, plus one pair on each side for the edge interpolation.
fn run_range(pairs: &[IsoPair], zone: Zone) -> (usize, usize) {
    let (r0, r1) = crate::geometry::run_around(pairs, zone.first, zone.last);
    (r0.saturating_sub(1), (r1 + 1).min(pairs.len() - 1))
}

#[cfg(test)]
mod tests {
    use super::*;
    use railsim_elastic::{Material, flexibilities, hertz_from_approach, kalker_coeffs};

    fn local(a_long: f64, b: f64) -> Local {
        Local {
            u: 0.0,
            chi: 1.0,
            l: 0.0,
            b,
            hc: hertz_coeffs_fast(a_long, b),
            k: 0.0,
            load: 0.0,
            width: 0.0,
            d: 0.0,
            a_long,
            s_r: 0.0,
            s_w: 0.0,
            b_exact: f64::NAN,
            qu_exact: (0.0, 0.0),
        }
    }

    fn rel(a: f64, b: f64) -> f64 {
        (a - b).abs() / b.abs()
    }

    /// A strip's ellipse is the Hertz ellipse of its own curvatures at the patch's approach, so
    /// on a constant-curvature geometry every strip takes the Hertz ellipse's Kalker
    /// coefficients and flexibilities, the linear-theory calibration of FASTSIM and FaStrip;
    /// where that ellipse is degenerate (no approach) the patch's equivalent ellipse stands in.
    #[test]
    fn a_strips_ellipse_is_the_hertz_ellipse_of_its_curvatures_at_the_approach() {
        let mat = Material::new(82e9, 0.28).unwrap();
        let table = KalkerTable::new(mat.nu).unwrap();
        let source = |delta0: f64, equivalent: (f64, f64, f64)| EllipseSource {
            delta0,
            equivalent,
            mu: 0.3,
            mat: &mat,
            kalker: &table,
        };
        let creep = Creepages {
            xi: 5e-3,
            eta: -3e-3,
            phi: 0.3,
        };
        for (a_curv, b_curv) in [(1.087, 1.667), (1.087, 0.2), (1.087, 8.0)] {
            let delta = 30e-6;
            let hz = hertz_from_approach(a_curv, b_curv, delta, &mat).unwrap();
            let li = local(a_curv, b_curv);
            let e = StripEllipse::new(li.a_long, li.b, &li.hc, &source(delta, (1.0, 1.0, 1.0)))
                .unwrap();
            assert_eq!(e.key, (a_curv, b_curv));
            // the fast Hertz coefficients against the exact ones: within 0.1 %
            assert!(rel(e.patch.a, hz.a) < 1e-3, "{} {}", e.patch.a, hz.a);
            assert!(rel(e.patch.b, hz.b) < 1e-3, "{} {}", e.patch.b, hz.b);
            let k = kalker_coeffs(hz.a, hz.b, mat.nu).unwrap();
            assert!(rel(e.patch.c11, k.c11) < 2e-3 && rel(e.patch.c23, k.c23) < 2e-3);
            let want = FlexibilityBlend::new(hz.a, hz.b, hz.n, 0.3, &mat)
                .unwrap()
                .at(&creep);
            let got = e.blend.at(&creep);
            for (g, w) in [(got.l1, want.l1), (got.l2, want.l2), (got.l3, want.l3)] {
                assert!(rel(g, w) < 3e-3, "{g} {w}");
            }
            // the blend moved the flexibilities: this creepage is not in the linear range
            let base = flexibilities(hz.a, hz.b, &mat).unwrap();
            let moved = [(got.l1, base.l1), (got.l2, base.l2), (got.l3, base.l3)]
                .iter()
                .map(|&(g, b)| rel(g, b))
                .fold(0.0, f64::max);
            assert!(moved > 1e-2, "{moved}");
        }
        let eq = (4e-3, 5e-3, 1e4);
        let li = local(1.087, 1.667);
        let e = StripEllipse::new(li.a_long, li.b, &li.hc, &source(0.0, eq)).unwrap();
        assert_eq!((e.patch.a, e.patch.b), (eq.0, eq.1));
        let want = FlexibilityBlend::new(eq.0, eq.1, eq.2, 0.3, &mat)
            .unwrap()
            .at(&creep);
        assert_eq!(e.blend.at(&creep).l2, want.l2);
    }
}
