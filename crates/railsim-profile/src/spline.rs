//! Parametric smoothing cubic spline (seed paper §3.1; Reinsch 1967).

use crate::ProfileError;

/// 5-point Gauss-Legendre nodes on [-1, 1].
const GL_X: [f64; 5] = [
    -0.906_179_845_938_664,
    -0.538_469_310_105_683,
    0.0,
    0.538_469_310_105_683,
    0.906_179_845_938_664,
];
/// 5-point Gauss-Legendre weights.
const GL_W: [f64; 5] = [
    0.236_926_885_056_189,
    0.478_628_670_499_366,
    0.568_888_888_888_889,
    0.478_628_670_499_366,
    0.236_926_885_056_189,
];

/// A parametric smoothing cubic spline (y(u), z(u)) over the cumulative chord length u of the
/// data points.
///
/// Each coordinate f minimises `Σ w_i (f(u_i) - f_i)² + λ ∫ f''(u)² du` (λ = `smoothing`,
/// \[m³\] for data in metres and dimensionless weights). This is the penalised form of Reinsch's
/// smoothing spline (C. H. Reinsch, "Smoothing by spline functions", Numer. Math. 10, 1967),
/// solved as in Reinsch's algorithm with the knot second derivatives as unknowns:
/// `(R + λ Qᵀ W⁻¹ Q) γ = Qᵀ f`, `g = f - λ W⁻¹ Q γ` (a symmetric positive-definite
/// pentadiagonal system). λ = 0 gives the interpolating natural cubic spline; the end
/// conditions are natural (zero second derivative) for every λ. The seed paper (Jalili &
/// Salehi 2011, §3.1) uses a smoothing cubic spline for measured profiles, with first and
/// second derivatives taken from the spline; the parametric form here also handles vertical
/// parts of an outline.
#[derive(Clone, Debug)]
pub struct SmoothingSpline {
    /// \[m\] knots (cumulative chord length of the data points)
    u: Vec<f64>,
    /// per segment, per coordinate: coefficients a, b, c, d of a + b t + c t² + d t³,
    /// t = u - u_i
    coef: Vec<[[f64; 4]; 2]>,
    /// \[m\] cumulative arc length at the knots
    s_knot: Vec<f64>,
}

impl SmoothingSpline {
    /// Fits the spline to `points` \[m\] with optional positive `weights` (default 1) and the
    /// smoothing parameter `smoothing` >= 0 (0 = interpolating). Needs at least 3 points;
    /// consecutive points must be distinct.
    pub fn fit(
        points: &[[f64; 2]],
        weights: Option<&[f64]>,
        smoothing: f64,
    ) -> Result<Self, ProfileError> {
        let n = points.len();
        let bad = |what: &str, found: String, expected: &str| ProfileError::InvalidArgument {
            source_name: "SmoothingSpline::fit".into(),
            what: what.into(),
            found,
            expected: expected.into(),
        };
        if n < 3 {
            return Err(bad("point count", n.to_string(), "at least 3 points"));
        }
        if !(smoothing.is_finite() && smoothing >= 0.0) {
            return Err(bad(
                "smoothing",
                smoothing.to_string(),
                "a finite number >= 0",
            ));
        }
        if let Some(w) = weights {
            if w.len() != n {
                return Err(bad(
                    "weights",
                    format!("{} weights", w.len()),
                    "one weight per point",
                ));
            }
            if let Some(i) = w.iter().position(|x| !(x.is_finite() && *x > 0.0)) {
                return Err(bad(
                    "weight",
                    format!("{} at point {}", w[i], i + 1),
                    "finite and > 0",
                ));
            }
        }
        let mut u = vec![0.0; n];
        for i in 1..n {
            let (a, b) = (points[i - 1], points[i]);
            if !(a[0].is_finite() && a[1].is_finite() && b[0].is_finite() && b[1].is_finite()) {
                return Err(bad(
                    "point",
                    format!("{:?} or {:?} at points {}, {}", a, b, i, i + 1),
                    "finite coordinates",
                ));
            }
            let h = (b[0] - a[0]).hypot(b[1] - a[1]);
            if h <= 0.0 {
                return Err(bad(
                    "point",
                    format!("point {} repeats point {}", i + 1, i),
                    "distinct consecutive points",
                ));
            }
            u[i] = u[i - 1] + h;
        }
        let h: Vec<f64> = u.windows(2).map(|w| w[1] - w[0]).collect();
        let winv = |i: usize| weights.map_or(1.0, |w| 1.0 / w[i]);
        let m = n - 2; // interior unknowns gamma_1..gamma_{n-2}
        // Q (n x m): column j (interior knot j+1) has entries at rows j, j+1, j+2.
        let q =
            |j: usize| -> [f64; 3] { [1.0 / h[j], -1.0 / h[j] - 1.0 / h[j + 1], 1.0 / h[j + 1]] };
        // Band of A = R + λ Qᵀ W⁻¹ Q: diag, first and second off-diagonals.
        let lam = smoothing;
        let mut a0 = vec![0.0; m];
        let mut a1 = vec![0.0; m];
        let mut a2 = vec![0.0; m];
        for j in 0..m {
            let qj = q(j);
            a0[j] = (h[j] + h[j + 1]) / 3.0
                + lam
                    * (qj[0] * qj[0] * winv(j)
                        + qj[1] * qj[1] * winv(j + 1)
                        + qj[2] * qj[2] * winv(j + 2));
            if j + 1 < m {
                let qk = q(j + 1);
                a1[j] = h[j + 1] / 6.0
                    + lam * (qj[1] * qk[0] * winv(j + 1) + qj[2] * qk[1] * winv(j + 2));
            }
            if j + 2 < m {
                let qk = q(j + 2);
                a2[j] = lam * qj[2] * qk[0] * winv(j + 2);
            }
        }
        // Right-hand sides Qᵀ f for both coordinates.
        let mut rhs = vec![[0.0; 2]; m];
        for j in 0..m {
            let qj = q(j);
            for c in 0..2 {
                rhs[j][c] =
                    qj[0] * points[j][c] + qj[1] * points[j + 1][c] + qj[2] * points[j + 2][c];
            }
        }
        let gamma_int = solve_penta(&a0, &a1, &a2, rhs).ok_or_else(|| {
            bad(
                "spline system",
                "not positive definite".into(),
                "well-separated points",
            )
        })?;
        let mut gamma = vec![[0.0; 2]; n];
        gamma[1..(m + 1)].copy_from_slice(&gamma_int[..m]);
        // g = f - λ W⁻¹ Q γ
        let mut g: Vec<[f64; 2]> = points.to_vec();
        if lam > 0.0 {
            for j in 0..m {
                let qj = q(j);
                for c in 0..2 {
                    for k in 0..3 {
                        g[j + k][c] -= lam * winv(j + k) * qj[k] * gamma_int[j][c];
                    }
                }
            }
        }
        let mut coef = Vec::with_capacity(n - 1);
        for i in 0..n - 1 {
            let hi = h[i];
            let mut seg = [[0.0; 4]; 2];
            for c in 0..2 {
                let (g0, g1, m0, m1) = (g[i][c], g[i + 1][c], gamma[i][c], gamma[i + 1][c]);
                seg[c] = [
                    g0,
                    (g1 - g0) / hi - hi * (2.0 * m0 + m1) / 6.0,
                    m0 / 2.0,
                    (m1 - m0) / (6.0 * hi),
                ];
            }
            coef.push(seg);
        }
        let mut sp = SmoothingSpline {
            u,
            coef,
            s_knot: Vec::new(),
        };
        let mut s_knot = vec![0.0; n];
        for i in 0..n - 1 {
            s_knot[i + 1] = s_knot[i] + sp.segment_length(i, sp.u[i + 1]);
        }
        sp.s_knot = s_knot;
        Ok(sp)
    }

    /// Index of the segment containing `u` (clamped).
    fn segment(&self, u: f64) -> usize {
        let k = self.u.partition_point(|&x| x <= u);
        k.clamp(1, self.u.len() - 1) - 1
    }

    /// Position, first and second derivative with respect to u at `u` \[m\]. Outside the
    /// parameter range the end cubics are extrapolated.
    pub fn eval(&self, u: f64) -> ([f64; 2], [f64; 2], [f64; 2]) {
        let i = self.segment(u);
        let t = u - self.u[i];
        let mut p = [0.0; 2];
        let mut d1 = [0.0; 2];
        let mut d2 = [0.0; 2];
        for c in 0..2 {
            let [a, b, cc, d] = self.coef[i][c];
            p[c] = a + t * (b + t * (cc + t * d));
            d1[c] = b + t * (2.0 * cc + 3.0 * t * d);
            d2[c] = 2.0 * cc + 6.0 * t * d;
        }
        (p, d1, d2)
    }

    /// |d(position)/du| of segment `i`'s cubic at `u`.
    fn speed_in(&self, i: usize, u: f64) -> f64 {
        let t = u - self.u[i];
        let [[_, bx, cx, dx], [_, by, cy, dy]] = self.coef[i];
        let vx = bx + t * (2.0 * cx + 3.0 * t * dx);
        let vy = by + t * (2.0 * cy + 3.0 * t * dy);
        vx.hypot(vy)
    }

    /// Arc length \[m\] of segment `i` from its start to `u` (5-point Gauss-Legendre).
    fn segment_length(&self, i: usize, u: f64) -> f64 {
        let (a, b) = (self.u[i], u);
        let half = 0.5 * (b - a);
        let mid = 0.5 * (a + b);
        GL_X.iter()
            .zip(GL_W)
            .map(|(x, w)| w * self.speed_in(i, mid + half * x))
            .sum::<f64>()
            * half
    }

    /// Total arc length \[m\] (5-point Gauss-Legendre on each segment).
    pub fn arc_length(&self) -> f64 {
        self.s_knot[self.s_knot.len() - 1]
    }

    /// Arc length \[m\] from the start to parameter `u` (clamped to the parameter range).
    pub fn arc_length_at(&self, u: f64) -> f64 {
        let (u0, u1) = self.param_range();
        let u = u.clamp(u0, u1);
        let i = self.segment(u);
        self.s_knot[i] + self.segment_length(i, u)
    }

    /// Parameter u \[m\] at arc length `s` \[m\] (clamped), by safeguarded Newton iteration.
    pub fn param_at_arc_length(&self, s: f64) -> f64 {
        let total = self.arc_length();
        let s = s.clamp(0.0, total);
        let k = self.s_knot.partition_point(|&x| x <= s);
        self.param_in_segment(k.clamp(1, self.s_knot.len() - 1) - 1, s)
    }

    /// Parameters at the arc lengths `s` (ascending, each clamped), as
    /// [`SmoothingSpline::param_at_arc_length`] gives them one by one, the segments found by a
    /// walk instead of a search.
    pub fn params_at_arc_lengths(&self, s: impl Iterator<Item = f64>) -> Vec<f64> {
        let total = self.arc_length();
        let last = self.s_knot.len() - 2;
        let mut i = 0;
        s.map(|s| {
            let s = s.clamp(0.0, total);
            // the segment of `param_at_arc_length`: the last knot at or before s
            while i < last && self.s_knot[i + 1] <= s {
                i += 1;
            }
            self.param_in_segment(i, s)
        })
        .collect()
    }

    /// Parameter u at arc length `s` (within `[0, arc_length]`) on segment `i`.
    fn param_in_segment(&self, i: usize, s: f64) -> f64 {
        let (mut lo, mut hi) = (self.u[i], self.u[i + 1]);
        let target = s - self.s_knot[i];
        let seg = self.s_knot[i + 1] - self.s_knot[i];
        let mut u = lo + (hi - lo) * if seg > 0.0 { target / seg } else { 0.0 };
        for _ in 0..50 {
            let f = self.segment_length(i, u) - target;
            if f > 0.0 {
                hi = u;
            } else {
                lo = u;
            }
            let sp = self.speed_in(i, u);
            let mut next = if sp > 0.0 {
                u - f / sp
            } else {
                0.5 * (lo + hi)
            };
            if !(next > lo && next < hi) {
                next = 0.5 * (lo + hi);
            }
            if (next - u).abs() <= 1e-15 * (1.0 + u.abs()) {
                return next;
            }
            u = next;
        }
        u
    }

    /// The parameter range (first knot, last knot) \[m\].
    pub fn param_range(&self) -> (f64, f64) {
        (self.u[0], self.u[self.u.len() - 1])
    }

    /// \[m\] the knots (cumulative chord length).
    pub fn knots(&self) -> &[f64] {
        &self.u
    }
}

/// Solves the symmetric positive-definite pentadiagonal system with diagonal `d`, first and
/// second super-diagonals `e`, `f` by an LDLᵀ factorisation, for two right-hand sides.
fn solve_penta(d: &[f64], e: &[f64], f: &[f64], mut b: Vec<[f64; 2]>) -> Option<Vec<[f64; 2]>> {
    let m = d.len();
    if m == 0 {
        return Some(b);
    }
    // L has unit diagonal with sub-diagonals l1 (i, i-1) and l2 (i, i-2); D diagonal dd.
    let mut dd = vec![0.0; m];
    let mut l1 = vec![0.0; m];
    let mut l2 = vec![0.0; m];
    for i in 0..m {
        if i >= 2 {
            l2[i] = f[i - 2] / dd[i - 2];
        }
        if i >= 1 {
            let mut v = e[i - 1];
            if i >= 2 {
                v -= l2[i] * dd[i - 2] * l1[i - 1];
            }
            l1[i] = v / dd[i - 1];
        }
        let mut v = d[i];
        if i >= 1 {
            v -= l1[i] * l1[i] * dd[i - 1];
        }
        if i >= 2 {
            v -= l2[i] * l2[i] * dd[i - 2];
        }
        if !(v > 0.0 && v.is_finite()) {
            return None;
        }
        dd[i] = v;
    }
    for c in 0..2 {
        for i in 0..m {
            if i >= 1 {
                b[i][c] -= l1[i] * b[i - 1][c];
            }
            if i >= 2 {
                b[i][c] -= l2[i] * b[i - 2][c];
            }
        }
        for i in 0..m {
            b[i][c] /= dd[i];
        }
        for i in (0..m).rev() {
            if i + 1 < m {
                b[i][c] -= l1[i + 1] * b[i + 1][c];
            }
            if i + 2 < m {
                b[i][c] -= l2[i + 2] * b[i + 2][c];
            }
        }
    }
    Some(b)
}
