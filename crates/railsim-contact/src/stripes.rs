//! STRIPES, the semi-Hertzian normal model of Ayasse & Chollet (VSD 43, 2005) on the isosceles
//! strips of Jalili & Salehi (2011, §3.4), with FASTSIM per strip for the tangential problem.
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
//! Tangential forces: FASTSIM (Kalker 1982) per strip, each strip a line of `nx` cells with
//! its own rigid slip (the wheel's velocity at the strip's locus point, which carries the spin
//! variation across the patch), and the flexibilities of the patch's area- and
//! aspect-preserving equivalent ellipse (Kik & Piotrowski 2008, as CONTACT does).

use railsim_elastic::{
    Creepages, TractionBound, blended_flexibilities, fastsim_strip, hertz_coeffs_fast, stripes_epsilon,
};

use crate::error::ContactError;
use crate::model::{PatchForces, PatchInput};
use crate::patch::{B_MIN, longitudinal_curvature, mid};

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
    l: f64,
    b: f64,
    hc: railsim_elastic::HertzCoeffs,
    eps: f64,
}

/// One strip of a STRIPES patch.
#[derive(Clone, Copy, Debug, Default)]
pub struct Strip {
    /// [m] lateral coordinate in the patch plane, from the reference point
    pub l: f64,
    /// [m] width carried by the strip
    pub w: f64,
    /// [m] virtual interpenetration h_i
    pub h: f64,
    /// [N/m] line load
    pub q: f64,
    /// [m] half-length
    pub a: f64,
    /// [m] longitudinal position of the strip centre relative to the reference point
    pub x: f64,
    /// index of the isosceles pair
    pub pair: usize,
}

/// Normal and tangential solution of one patch with STRIPES + FASTSIM per strip.
pub fn solve(
    input: &PatchInput<'_>,
    variant: StripesVariant,
    nx: usize,
    bound: TractionBound,
    strips: &mut Vec<Strip>,
    local: &mut Vec<Local>,
) -> Result<PatchForces, ContactError> {
    let fr = &input.frame;
    let pairs = input.pairs;
    let mat = input.pair.material;
    let e_star = mat.e_star();
    let hc0 = hertz_coeffs_fast(fr.a_curv, fr.b_curv);
    let eps0 = stripes_epsilon(&hc0, fr.a_curv, fr.b_curv);
    let delta0 = fr.delta0;
    let m0 = [
        0.5 * (fr.rail_point[0] + fr.wheel_point[1]),
        0.5 * (fr.rail_point[1] + fr.wheel_point[2]),
    ];
    let lo = input.zone.first.saturating_sub(1);
    let hi = (input.zone.last + 1).min(pairs.len() - 1);
    // Per pair: local curvatures and Hertz coefficients, the interpenetration along the patch
    // normal, the lateral coordinate, and u = virtual interpenetration (positive inside).
    local.clear();
    for i in lo..=hi {
        let p = &pairs[i];
        let a_i = longitudinal_curvature(p.rho, p.rho_slope);
        let kw = if input.yawed {
            crate::geometry::locus_curvature(input.pair, input.ctx, p.s_w)
        } else {
            p.kappa_w
        };
        let b_i = (0.5 * (kw - p.kappa_r)).max(B_MIN);
        let hc = hertz_coeffs_fast(a_i, b_i);
        let eps_i = stripes_epsilon(&hc, a_i, b_i);
        let d = -p.gap * (p.n[0] * fr.n[0] + p.n[1] * fr.n[1]);
        let eps = match variant {
            StripesVariant::Seed => eps0,
            StripesVariant::LocalEpsilon => eps_i,
        };
        let m = mid(p);
        local.push(Local {
            u: d - (1.0 - eps) * delta0,
            l: (m[0] - m0[0]) * fr.t[0] + (m[1] - m0[1]) * fr.t[1],
            b: b_i,
            hc,
            eps: eps_i,
        });
    }
    strips.clear();
    let mut l_min = f64::INFINITY;
    let mut l_max = f64::NEG_INFINITY;
    for i in lo..=hi {
        let li = &local[i - lo];
        if li.u <= 0.0 {
            continue;
        }
        // Width from the two neighbouring segments, clipped at the zero crossings of u.
        let mut w = 0.0;
        for j in [i.wrapping_sub(1), i + 1] {
            if j < lo || j > hi {
                continue;
            }
            let lj = &local[j - lo];
            let seg = (lj.l - li.l).abs();
            let reach = if lj.u > 0.0 { seg } else { seg * li.u / (li.u - lj.u) };
            w += 0.5 * reach;
            let edge = li.l + (lj.l - li.l).signum() * reach;
            l_min = l_min.min(edge);
            l_max = l_max.max(edge);
        }
        if w <= 0.0 {
            continue;
        }
        let q = e_star * li.u / (li.hc.n * li.hc.r * li.eps);
        let ac = (li.hc.n / li.hc.m).powi(2) * li.b;
        strips.push(Strip {
            l: li.l,
            w,
            h: li.u,
            q,
            a: (li.u / ac).sqrt(),
            x: pairs[i].x - fr.wheel_point[0],
            pair: i,
        });
    }
    if strips.is_empty() {
        return Ok(PatchForces::default());
    }
    let mut f = PatchForces::default();
    let mut area = 0.0;
    let mut a_max: f64 = 0.0;
    for s in strips.iter() {
        f.fn_ += s.q * s.w;
        let p0 = 2.0 * s.q / (std::f64::consts::PI * s.a);
        f.p_max = f.p_max.max(p0);
        area += 2.0 * s.a * s.w;
        a_max = a_max.max(s.a);
    }
    f.width = (l_max - l_min).max(0.0);
    f.length = 2.0 * a_max;
    f.area = area;
    f.n_elements = strips.len() as u32;
    // Equivalent ellipse (area and aspect preserved) for the flexibilities.
    let len = f.length.max(1e-9);
    let wid = f.width.max(1e-9);
    let r = (area / std::f64::consts::PI).sqrt();
    let a_eq = r * (len / wid).sqrt();
    let b_eq = r * (wid / len).sqrt();
    let flex = blended_flexibilities(a_eq, b_eq, f.fn_, input.pair.mu, &input.creep, &mat)?;
    let mut n_adh = 0u32;
    let mut n_cells = 0u32;
    for s in strips.iter() {
        let p = &pairs[s.pair];
        let creep: Creepages = input.kin.creepages([p.x, p.a[0], p.a[1]], fr.t, p.n);
        let p0 = 2.0 * s.q / (std::f64::consts::PI * s.a);
        let st = fastsim_strip(0.0, s.w, s.x, s.a, p0, bound, &creep, &flex, input.pair.mu, nx);
        f.fx += st.fx;
        f.fs += st.fy;
        f.mz += st.mz - s.l * st.fx;
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
