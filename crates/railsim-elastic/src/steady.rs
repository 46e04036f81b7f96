//! Kalker's exact steady-rolling tangential problem on a grid of rectangular elements: the
//! tangential counterpart of [`crate::halfspace`], and the reference that FASTSIM and FaStrip are
//! measured against.
//!
//! Formulation (J.J. Kalker, *Three-dimensional elastic bodies in rolling contact*, Kluwer 1990,
//! ch. 5; the discretisation of CONTACT's steady-state solver, E.A.H. Vollebregt, CONTACT user
//! guide; contact-theory note §3.1 and §4.1):
//!
//! - rolling in +x: material enters the patch at the leading edge (largest x) and leaves at the
//!   trailing edge;
//! - piecewise-constant tractions `p = (p_x, p_y)` on the cells; the relative tangential surface
//!   displacement of the two half-spaces (quasi-identical materials: no normal–tangential
//!   coupling) is `u_I = sum_J A_IJ p_J` with Love–Cerruti influence coefficients of a uniform
//!   traction on a rectangle, both bodies counted through the combined `G`, `nu`:
//!   `A^xx = [(1-nu) j1 + j2]/(pi G)`, `A^yy = [j1 + (1-nu) j2]/(pi G)`,
//!   `A^xy = nu [-r]/(pi G)`, where `j1`, `j2`, `[-r]` are the corner differences of
//!   `x ln(y + r)`, `y ln(x + r)` and `-r` (contact-theory note §4.1; they are the exact
//!   integrals over the rectangle of Cerruti's point-load solution, Johnson 1985 eq. 3.86);
//! - slip per unit rolling distance at cell `I`, with `U` the cell just upstream (at `x + dx`):
//!   `s_I = w_I - (u_U - u_I)/dx`, `w_I` the rigid slip (creepage) at the cell;
//! - conditions: adhesion `s_I = 0` where `|p_I| <= mu p_n,I`; slip `p_I = -mu p_n,I s_I/|s_I|`
//!   elsewhere.
//!
//! Solver: Gauss–Seidel over the cells in contact, row by row from the leading to the trailing
//! edge (the order in which material passes through the patch), each cell solved exactly for its
//! own traction with the others fixed (a 2×2 diagonal system in adhesion, a scalar Newton
//! iteration on the traction bound in slip), as Kalker's and CONTACT's steady-state Gauss–Seidel
//! solvers do. The displacement field is updated after each cell change, so a sweep costs
//! O(cells in contact × grid cells).
//!
//! In the simplified theory (FASTSIM) `u = L p`; with that flexibility the same discrete
//! equations give FASTSIM's marching rule `p_I = p_U - dx w_I / L`, so both share one sign
//! convention: forces act on the upper body and oppose the creepage.

use std::f64::consts::PI;

use crate::error::{ElasticError, non_negative, positive};
use crate::halfspace::Grid;
use crate::material::Material;

/// `x ln(y + r)` (`r = sqrt(x^2 + y^2)`) up to terms that cancel in a corner difference:
/// `x asinh(y/|x|)`, which is `x ln(y + r) - x ln|x|`; 0 at `x = 0` (its limit).
fn x_asinh(x: f64, y: f64) -> f64 {
    if x == 0.0 {
        0.0
    } else {
        x * (y / x.abs()).asinh()
    }
}

/// Corner difference `F(x2,y2) - F(x1,y2) - F(x2,y1) + F(x1,y1)`.
fn corners(f: impl Fn(f64, f64) -> f64, x1: f64, x2: f64, y1: f64, y2: f64) -> f64 {
    f(x2, y2) - f(x1, y2) - f(x2, y1) + f(x1, y1)
}

/// Tangential influence coefficients `(A^xx, A^yy, A^xy)` [m/Pa]: relative tangential
/// displacement at a point due to a unit uniform tangential traction on a rectangle of size
/// `hx` x `hy` \[m\] whose centre lies at offset (`off_x`, `off_y`) \[m\] from the point (Love
/// 1929 / Cerruti; contact-theory note §4.1, CONTACT `elascf_pcwcns`). `A^xx` and `A^yy` are
/// even in both offsets, `A^xy` odd in each.
///
/// The `x ln|x|` parts dropped by `x asinh(y/|x|)` cancel between the two corners that share an
/// `x`, so the corner differences are those of `x ln(y + r)` exactly.
pub fn cerruti_influence(
    off_x: f64,
    off_y: f64,
    hx: f64,
    hy: f64,
    mat: &Material,
) -> (f64, f64, f64) {
    let x1 = off_x - 0.5 * hx;
    let x2 = off_x + 0.5 * hx;
    let y1 = off_y - 0.5 * hy;
    let y2 = off_y + 0.5 * hy;
    // j1: x ln(y + r); j2: y ln(x + r)
    let j1 = corners(x_asinh, x1, x2, y1, y2);
    let j2 = corners(|x, y| x_asinh(y, x), x1, x2, y1, y2);
    let jr = -corners(f64::hypot, x1, x2, y1, y2);
    let nu = mat.nu;
    let s = 1.0 / (PI * mat.g);
    (
        s * ((1.0 - nu) * j1 + j2),
        s * (j1 + (1.0 - nu) * j2),
        s * nu * jr,
    )
}

/// Result of a steady-rolling tangential solve.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SteadySolution {
    /// \[N\] longitudinal force on the upper body
    pub fx: f64,
    /// \[N\] lateral force on the upper body
    pub fy: f64,
    /// [N m] moment about the normal through the grid origin (x = 0, y = 0)
    pub mz: f64,
    /// cells in contact (p_n > 0)
    pub n_contact: usize,
    /// cells in adhesion
    pub n_adhesion: usize,
    /// Gauss–Seidel sweeps done
    pub sweeps: usize,
    /// largest traction change of the last sweep relative to the largest traction
    pub residual: f64,
}

/// Reusable solver for one grid: the influence kernel and the traction fields.
#[derive(Clone, Debug)]
pub struct SteadyRollingSolver {
    grid: Grid,
    /// kernel width along x: offsets -nx ..= nx
    kw: usize,
    /// A^xx, A^yy, A^xy at signed offsets (J - I): index `(dix + nx) + kw (diy + ny - 1)`
    kxx: Vec<f64>,
    kyy: Vec<f64>,
    kxy: Vec<f64>,
    /// traction of each grid cell \[Pa\], `ix + nx iy`
    px: Vec<f64>,
    py: Vec<f64>,
    /// traction differences `dp_J = p_J - p_(J+1)` (minus the upstream neighbour) on the grid
    /// extended by one column on the trailing side: index `(ix + 1) + (nx + 1) iy`
    dpx: Vec<f64>,
    dpy: Vec<f64>,
    /// whether each cell was in adhesion at its last update
    adhesion: Vec<bool>,
    /// cells in contact, in solving order (rows, trailing to leading edge)
    active: Vec<usize>,
    /// cells of the extended grid where `dp` can be non-zero (contact cells and the exterior
    /// cell just behind each trailing edge), as (extended index, ix + 1, iy)
    support: Vec<(usize, usize, usize)>,
}

impl SteadyRollingSolver {
    /// Build the influence kernel of `grid` for the combined material `mat`.
    pub fn new(grid: Grid, mat: &Material) -> Result<Self, ElasticError> {
        let mut s = Self {
            grid,
            kw: 0,
            kxx: Vec::new(),
            kyy: Vec::new(),
            kxy: Vec::new(),
            px: Vec::new(),
            py: Vec::new(),
            dpx: Vec::new(),
            dpy: Vec::new(),
            adhesion: Vec::new(),
            active: Vec::new(),
            support: Vec::new(),
        };
        s.set_grid(grid, mat)?;
        Ok(s)
    }

    /// Switch to another grid (or material), reusing the buffers: nothing is allocated once they
    /// have grown to the largest grid. The tractions are reset to zero.
    pub fn set_grid(&mut self, grid: Grid, mat: &Material) -> Result<(), ElasticError> {
        grid.check()?;
        positive("G [Pa]", mat.g)?;
        let (nx, ny) = (grid.nx, grid.ny);
        let kw = 2 * nx + 1;
        let kh = 2 * ny - 1;
        self.grid = grid;
        self.kw = kw;
        for (v, len) in [
            (&mut self.kxx, kw * kh),
            (&mut self.kyy, kw * kh),
            (&mut self.kxy, kw * kh),
            (&mut self.px, nx * ny),
            (&mut self.py, nx * ny),
            (&mut self.dpx, (nx + 1) * ny),
            (&mut self.dpy, (nx + 1) * ny),
        ] {
            v.clear();
            v.resize(len, 0.0);
        }
        self.adhesion.clear();
        self.adhesion.resize(nx * ny, true);
        self.active.reserve(nx * ny);
        self.support.reserve((nx + 1) * ny);
        // Compute one quadrant and mirror it: xx, yy even, xy odd in each offset.
        for diy in 0..ny {
            for dix in 0..=nx {
                let (axx, ayy, axy) = cerruti_influence(
                    dix as f64 * grid.dx,
                    diy as f64 * grid.dy,
                    grid.dx,
                    grid.dy,
                    mat,
                );
                for (sx, sy) in [(1i64, 1i64), (-1, 1), (1, -1), (-1, -1)] {
                    let ix = (nx as i64 + sx * dix as i64) as usize;
                    let iy = (ny as i64 - 1 + sy * diy as i64) as usize;
                    let k = ix + kw * iy;
                    self.kxx[k] = axx;
                    self.kyy[k] = ayy;
                    self.kxy[k] = (sx * sy) as f64 * axy;
                }
            }
        }
        Ok(())
    }

    /// The grid.
    pub fn grid(&self) -> &Grid {
        &self.grid
    }

    /// Tractions of the last solve \[Pa\], row-major (`ix + nx iy`).
    pub fn traction(&self) -> (&[f64], &[f64]) {
        (&self.px, &self.py)
    }

    /// `dp` of row `iy` recomputed from the tractions for the columns `ix_lo ..= ix_hi`
    /// (`ix_lo` may be -1, the exterior column behind the grid).
    fn update_dp(&mut self, iy: usize, ix_lo: i64, ix_hi: usize) {
        let nx = self.grid.nx;
        for ix in ix_lo..=ix_hi as i64 {
            let at = |v: &[f64], i: i64| -> f64 {
                if i >= 0 && (i as usize) < nx {
                    v[i as usize + nx * iy]
                } else {
                    0.0
                }
            };
            let e = (ix + 1) as usize + (nx + 1) * iy;
            self.dpx[e] = at(&self.px, ix) - at(&self.px, ix + 1);
            self.dpy[e] = at(&self.py, ix) - at(&self.py, ix + 1);
        }
    }

    /// Solve the steady-rolling problem for the normal pressure `pn` \[Pa\] and the rigid slip
    /// (creepages, dimensionless) `wx`, `wy` of each cell, row-major (`ix + nx iy`), friction
    /// coefficient `mu`. Rolling is in +x (leading edge toward the last column).
    ///
    /// Iteration (the block Gauss–Seidel of CONTACT's steady-state solver, Vollebregt, in our own
    /// formulation): the slip is written with the traction differences along the rows,
    /// `s_I = w_I + (1/dx) sum_J A_IJ dp_J`, `dp_J = p_J - p_upstream(J)` (summation by parts
    /// of the Toeplitz kernel). Cells are visited row by row from the trailing to the leading
    /// edge; a change of the traction of cell `I` is carried along by the adhesion cells
    /// downstream of it up to the first cell in slip or outside the contact (their `dp` is
    /// kept), so the cell's own coefficient is `(A(0) - A(m))/dx`, `m` the length of that
    /// stretch. This keeps the iteration convergent where the plain element-wise Gauss–Seidel on
    /// the tractions diverges (its error grows with the number of cells along a row).
    ///
    /// `warm`: start from the tractions of the previous solve on this grid (clipped to the new
    /// bound) instead of zero. Stops when a sweep changes no traction by more than `tol` times
    /// the largest traction bound, or with [`ElasticError::NotConverged`] after `max_sweeps`.
    #[allow(clippy::too_many_arguments)]
    pub fn solve(
        &mut self,
        pn: &[f64],
        wx: &[f64],
        wy: &[f64],
        mu: f64,
        tol: f64,
        max_sweeps: usize,
        warm: bool,
    ) -> Result<SteadySolution, ElasticError> {
        let (nx, ny) = (self.grid.nx, self.grid.ny);
        let n = nx * ny;
        for (name, len) in [
            ("pn.len()", pn.len()),
            ("wx.len()", wx.len()),
            ("wy.len()", wy.len()),
        ] {
            if len != n {
                return Err(ElasticError::InvalidSize {
                    name,
                    found: len,
                    expected: format!("one value per grid cell ({nx} x {ny} = {n})"),
                });
            }
        }
        non_negative("mu [-]", mu)?;
        positive("tol [-]", tol)?;
        for k in 0..n {
            non_negative("pn [Pa]", pn[k])?;
            crate::error::finite("wx [-]", wx[k])?;
            crate::error::finite("wy [-]", wy[k])?;
        }
        let dx = self.grid.dx;
        let inv_dx = 1.0 / dx;
        self.active.clear();
        self.support.clear();
        for iy in 0..ny {
            for ix in 0..nx {
                let k = ix + nx * iy;
                let here = pn[k] > 0.0;
                let up = ix + 1 < nx && pn[k + 1] > 0.0;
                if here {
                    self.active.push(k);
                }
                if here || up {
                    self.support.push((ix + 1 + (nx + 1) * iy, ix + 1, iy));
                }
            }
            // the exterior cell behind a contact cell in the first column
            if pn[nx * iy] > 0.0 {
                self.support.push(((nx + 1) * iy, 0, iy));
            }
        }
        // Start: previous tractions clipped to the new bound (state kept), or zero in adhesion.
        for k in 0..n {
            let g = mu * pn[k];
            let (mut x, mut y) = if warm {
                (self.px[k], self.py[k])
            } else {
                self.adhesion[k] = true;
                (0.0, 0.0)
            };
            let m = x.hypot(y);
            if m > g {
                let f = if m > 0.0 { g / m } else { 0.0 };
                x *= f;
                y *= f;
            }
            self.px[k] = x;
            self.py[k] = y;
        }
        for iy in 0..ny {
            self.update_dp(iy, -1, nx - 1);
        }
        let (kw, cx0, cy0) = (self.kw, nx as i64, ny as i64 - 1);
        let centre = nx + kw * (ny - 1);
        let mut residual = f64::INFINITY;
        let mut sweeps = 0;
        let mut n_adh = 0;
        while sweeps < max_sweeps {
            sweeps += 1;
            let mut change: f64 = 0.0;
            n_adh = 0;
            for i in 0..self.active.len() {
                let k = self.active[i];
                let (ix, iy) = (k % nx, k / nx);
                // slip with the current tractions: s = w + (1/dx) sum_J A(J - I) dp_J
                let (mut sx, mut sy) = (0.0, 0.0);
                for &(e, jx1, jy) in &self.support {
                    let (dpx, dpy) = (self.dpx[e], self.dpy[e]);
                    // offset J - I with jx = jx1 - 1
                    let kk = (jx1 as i64 - 1 - ix as i64 + cx0) as usize
                        + kw * (jy as i64 - iy as i64 + cy0) as usize;
                    let (axx, ayy, axy) = (self.kxx[kk], self.kyy[kk], self.kxy[kk]);
                    sx += axx * dpx + axy * dpy;
                    sy += axy * dpx + ayy * dpy;
                }
                let sx = wx[k] + sx * inv_dx;
                let sy = wy[k] + sy * inv_dx;
                // the adhesion stretch downstream that moves with this cell
                let mut jx = ix as i64 - 1;
                while jx >= 0
                    && pn[jx as usize + nx * iy] > 0.0
                    && self.adhesion[jx as usize + nx * iy]
                {
                    jx -= 1;
                }
                let m = (ix as i64 - jx) as usize;
                let bx = (self.kxx[centre] - self.kxx[centre - m]) * inv_dx;
                let by = (self.kyy[centre] - self.kyy[centre - m]) * inv_dx;
                let (px0, py0) = (self.px[k], self.py[k]);
                let cx = sx - bx * px0;
                let cy = sy - by * py0;
                let g = mu * pn[k];
                // adhesion: s = c + B p = 0
                let (mut px, mut py) = (-cx / bx, -cy / by);
                if px.hypot(py) <= g {
                    self.adhesion[k] = true;
                    n_adh += 1;
                } else {
                    self.adhesion[k] = false;
                    // slip: p = -(B + k I)^-1 c with |p| = g, k >= 0 (Newton on the bound; the
                    // magnitude falls monotonically and convexly in k)
                    let mut kk = 0.0f64;
                    for _ in 0..60 {
                        let (qx, qy) = (cx / (bx + kk), cy / (by + kk));
                        let mag = qx.hypot(qy);
                        let dm = -(qx * qx / (bx + kk) + qy * qy / (by + kk)) / mag.max(1e-300);
                        let next = (kk - (mag - g) / dm).max(0.0);
                        let done = (next - kk).abs() <= 1e-13 * (bx.min(by) + next);
                        kk = next;
                        if done {
                            break;
                        }
                    }
                    px = -cx / (bx + kk);
                    py = -cy / (by + kk);
                    let mag = px.hypot(py);
                    if mag > 0.0 {
                        px *= g / mag;
                        py *= g / mag;
                    }
                }
                let (dx_, dy_) = (px - px0, py - py0);
                if dx_ == 0.0 && dy_ == 0.0 {
                    continue;
                }
                change = change.max(dx_.hypot(dy_));
                self.px[k] = px;
                self.py[k] = py;
                // carry the change along the downstream adhesion stretch, within the bound
                for j in (jx + 1).max(0) as usize..ix {
                    let kj = j + nx * iy;
                    let (mut qx, mut qy) = (self.px[kj] + dx_, self.py[kj] + dy_);
                    let gj = mu * pn[kj];
                    let mag = qx.hypot(qy);
                    if mag > gj {
                        qx *= gj / mag;
                        qy *= gj / mag;
                    }
                    self.px[kj] = qx;
                    self.py[kj] = qy;
                }
                self.update_dp(iy, jx, ix);
            }
            // relative to the largest traction (not the bound, which may be far above it)
            let p_big = self
                .active
                .iter()
                .map(|&k| self.px[k].hypot(self.py[k]))
                .fold(0.0, f64::max);
            residual = if p_big > 0.0 { change / p_big } else { 0.0 };
            if residual <= tol {
                break;
            }
        }
        if residual > tol {
            return Err(ElasticError::NotConverged {
                solver: "steady-rolling Gauss-Seidel",
                iterations: sweeps,
                residual,
                tol,
            });
        }
        let da = self.grid.cell_area();
        let (mut fx, mut fy, mut mz) = (0.0, 0.0, 0.0);
        for &k in &self.active {
            let (x, y) = (self.grid.x(k % nx), self.grid.y(k / nx));
            fx += self.px[k];
            fy += self.py[k];
            mz += x * self.py[k] - y * self.px[k];
        }
        Ok(SteadySolution {
            fx: fx * da,
            fy: fy * da,
            mz: mz * da,
            n_contact: self.active.len(),
            n_adhesion: n_adh,
            sweeps,
            residual,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kalker::{Creepages, linear_kalker};

    fn mat() -> Material {
        Material::new(82e9, 0.28).unwrap()
    }

    /// Hertz-shaped pressure on an ellipse, on a grid 1.04 times its size, and the rigid slip of
    /// the creepages.
    fn ellipse_case(
        a: f64,
        b: f64,
        n_load: f64,
        creep: &Creepages,
        cells: usize,
    ) -> (Grid, Vec<f64>, Vec<f64>, Vec<f64>) {
        let grid = Grid::covering(cells, cells, -1.04 * a, 1.04 * a, -1.04 * b, 1.04 * b).unwrap();
        let p0 = 1.5 * n_load / (PI * a * b);
        let mut pn = vec![0.0; grid.len()];
        let mut wx = vec![0.0; grid.len()];
        let mut wy = vec![0.0; grid.len()];
        for iy in 0..grid.ny {
            for ix in 0..grid.nx {
                let (x, y) = (grid.x(ix), grid.y(iy));
                let q = 1.0 - (x / a).powi(2) - (y / b).powi(2);
                let k = ix + grid.nx * iy;
                pn[k] = if q > 0.0 { p0 * q.sqrt() } else { 0.0 };
                wx[k] = creep.xi - creep.phi * y;
                wy[k] = creep.eta + creep.phi * x;
            }
        }
        (grid, pn, wx, wy)
    }

    #[test]
    fn bad_input_is_an_error_naming_the_quantity() {
        let m = mat();
        let grid = Grid::covering(4, 4, -1e-3, 1e-3, -1e-3, 1e-3).unwrap();
        let mut s = SteadyRollingSolver::new(grid, &m).unwrap();
        let ok = vec![1e6; 16];
        let zero = vec![0.0; 16];
        let short = vec![0.0; 15];
        let e = s
            .solve(&ok, &short, &zero, 0.3, 1e-7, 100, false)
            .unwrap_err();
        assert!(e.to_string().contains("wx.len() = 15"), "{e}");
        let mut nan = zero.clone();
        nan[3] = f64::NAN;
        let e = s
            .solve(&ok, &zero, &nan, 0.3, 1e-7, 100, false)
            .unwrap_err();
        assert!(e.to_string().contains("wy [-]"), "{e}");
        let mut neg = ok.clone();
        neg[0] = -1.0;
        let e = s
            .solve(&neg, &zero, &zero, 0.3, 1e-7, 100, false)
            .unwrap_err();
        assert!(e.to_string().contains("pn [Pa]"), "{e}");
        let e = s
            .solve(&ok, &zero, &zero, -0.3, 1e-7, 100, false)
            .unwrap_err();
        assert!(e.to_string().contains("mu"), "{e}");
        // No creepage, no traction; an unloaded grid is not an error.
        let r = s.solve(&zero, &zero, &zero, 0.3, 1e-7, 100, false).unwrap();
        assert_eq!((r.fx, r.fy, r.n_contact), (0.0, 0.0, 0));
    }

    #[test]
    fn influence_coefficients_symmetry_and_self_term() {
        let m = mat();
        let h = 1e-3;
        let (axx, ayy, axy) = cerruti_influence(0.0, 0.0, h, h, &m);
        // square cell: j1 = j2 = 2 ln(1 + sqrt 2) h
        let j = 2.0 * (1.0 + 2f64.sqrt()).ln() * h;
        let expect = ((1.0 - m.nu) * j + j) / (PI * m.g);
        assert!((axx - expect).abs() < 1e-12 * expect);
        assert!((ayy - expect).abs() < 1e-12 * expect);
        assert!(axy.abs() < 1e-15 * expect);
        // xy odd in each offset, xx even
        let a = cerruti_influence(2.3e-3, 1.1e-3, h, 0.7 * h, &m);
        let b = cerruti_influence(-2.3e-3, 1.1e-3, h, 0.7 * h, &m);
        let c = cerruti_influence(-2.3e-3, -1.1e-3, h, 0.7 * h, &m);
        assert!((a.0 - b.0).abs() < 1e-12 * a.0 && (a.1 - c.1).abs() < 1e-12 * a.1);
        assert!((a.2 + b.2).abs() < 1e-12 * a.2.abs() && (a.2 - c.2).abs() < 1e-12 * a.2.abs());
        // far field: the rectangle acts as a point load (Cerruti): u_x = Q/(pi G) ((1-nu)/r + nu x^2/r^3)
        let (x, y) = (0.3, 0.2);
        let r = f64::hypot(x, y);
        let q = h * h;
        let (fxx, fyy, fxy) = cerruti_influence(x, y, h, h, &m);
        let s = q / (PI * m.g);
        let exx = s * ((1.0 - m.nu) / r + m.nu * x * x / r.powi(3));
        let eyy = s * ((1.0 - m.nu) / r + m.nu * y * y / r.powi(3));
        let exy = s * m.nu * x * y / r.powi(3);
        assert!((fxx - exx).abs() < 1e-5 * exx, "{fxx} {exx}");
        assert!((fyy - eyy).abs() < 1e-5 * eyy, "{fyy} {eyy}");
        assert!((fxy - exy).abs() < 1e-5 * exy, "{fxy} {exy}");
    }

    #[test]
    fn linear_limit_matches_kalker() {
        // Full adhesion (huge mu, tiny creepage) on Hertz ellipses: Kalker's C11, C22, C23 of the
        // table, up to the first-order discretisation error of piecewise-constant tractions
        // (measured +0.5..+1.1 % on C11, C22 and -1.8..-2.2 % on C23 at 40 x 40).
        let m = mat();
        let c = 5e-3;
        let mut worst: f64 = 0.0;
        for ratio in [0.5, 1.0, 2.0] {
            let a = c * f64::sqrt(ratio);
            let b = c / f64::sqrt(ratio);
            for creep in [
                Creepages {
                    xi: 1e-6,
                    eta: 0.0,
                    phi: 0.0,
                },
                Creepages {
                    xi: 0.0,
                    eta: 1e-6,
                    phi: 0.0,
                },
                Creepages {
                    xi: 0.0,
                    eta: 0.0,
                    phi: 1e-4,
                },
            ] {
                let (grid, pn, wx, wy) = ellipse_case(a, b, 1e5, &creep, 40);
                let mut s = SteadyRollingSolver::new(grid, &m).unwrap();
                let r = s.solve(&pn, &wx, &wy, 1e3, 1e-9, 500, false).unwrap();
                let k = linear_kalker(a, b, &creep, &m).unwrap();
                assert_eq!(r.n_adhesion, r.n_contact, "full adhesion expected");
                let (got, want) = if creep.xi != 0.0 {
                    (r.fx, k.fx)
                } else {
                    (r.fy, k.fy)
                };
                let e = (got - want) / want;
                assert!(got.signum() == want.signum(), "sign: {got} vs {want}");
                worst = worst.max(e.abs());
                assert!(
                    e.abs() < 0.03,
                    "a/b {ratio} {creep:?}: {got} vs Kalker {want} ({e:+.4})"
                );
                if creep.xi != 0.0 {
                    assert!(
                        r.fy.abs() < 1e-6 * r.fx.abs(),
                        "{} {} {}",
                        r.fy,
                        r.fx,
                        r.sweeps
                    );
                }
            }
        }
        assert!(worst > 0.0);
    }

    #[test]
    fn saturates_at_mu_n_and_warm_start_agrees() {
        let m = mat();
        let (a, b, n) = (4e-3, 6e-3, 5e4);
        let creep = Creepages {
            xi: 0.02,
            eta: -0.01,
            phi: 0.5,
        };
        let (grid, pn, wx, wy) = ellipse_case(a, b, n, &creep, 24);
        let mut s = SteadyRollingSolver::new(grid, &m).unwrap();
        let r = s.solve(&pn, &wx, &wy, 0.3, 1e-9, 500, false).unwrap();
        let load: f64 = pn.iter().sum::<f64>() * grid.cell_area();
        assert_eq!(r.n_adhesion, 0);
        let f = r.fx.hypot(r.fy);
        assert!(
            f < 0.3 * load && f > 0.9 * 0.3 * load,
            "{f} vs {}",
            0.3 * load
        );
        // A solve that starts from the converged tractions needs one sweep and agrees.
        let r2 = s.solve(&pn, &wx, &wy, 0.3, 1e-9, 500, true).unwrap();
        assert!(r2.sweeps <= 2, "{}", r2.sweeps);
        assert!((r2.fx - r.fx).abs() < 1e-6 * f && (r2.fy - r.fy).abs() < 1e-6 * f);
        // Pure longitudinal creepage far beyond saturation: every cell at the bound, |F| = mu N up
        // to the small lateral slip components that the A^xy coupling gives each cell.
        let creep = Creepages {
            xi: 0.05,
            eta: 0.0,
            phi: 0.0,
        };
        let (_, pn, wx, wy) = ellipse_case(a, b, n, &creep, 24);
        let r = s.solve(&pn, &wx, &wy, 0.3, 1e-9, 500, false).unwrap();
        assert!(
            (r.fx + 0.3 * load).abs() < 1e-4 * load,
            "{} vs {}",
            r.fx,
            -0.3 * load
        );
        assert!(r.fx > -0.3 * load);
    }

    #[test]
    fn carter_two_dimensional_partial_slip() {
        // A long strip of cylinder contact (b >> a): the middle row follows Carter's 2-D solution
        // F'/(mu N') = -[1 - (1 - xi/xi_c)^2], xi_c = 4 mu N'(1-nu)/(pi a G) (contact-theory
        // note §3.5). A 2-D line contact is approximated by an ellipse 30 times longer than wide;
        // the centre row's line load is compared.
        let m = mat();
        let (a, b) = (1e-3, 30e-3);
        let nx = 40;
        let ny = 61;
        let grid = Grid::covering(nx, ny, -1.04 * a, 1.04 * a, -b, b).unwrap();
        let n_line = 178.9e3; // N/m
        let p0 = 2.0 * n_line / (PI * a);
        let mu = 0.3;
        let xi_c = 4.0 * mu * n_line * (1.0 - m.nu) / (PI * a * m.g);
        let mut pn = vec![0.0; grid.len()];
        for iy in 0..ny {
            for ix in 0..nx {
                let x = grid.x(ix);
                let q = 1.0 - (x / a).powi(2);
                pn[ix + nx * iy] = if q > 0.0 { p0 * q.sqrt() } else { 0.0 };
            }
        }
        let mut s = SteadyRollingSolver::new(grid, &m).unwrap();
        for frac in [0.2, 0.4, 0.7] {
            let xi = frac * xi_c;
            let wx = vec![xi; grid.len()];
            let wy = vec![0.0; grid.len()];
            s.solve(&pn, &wx, &wy, mu, 1e-10, 2000, false).unwrap();
            let mid = ny / 2;
            let (px, _) = s.traction();
            let line: f64 = px[nx * mid..nx * (mid + 1)].iter().sum::<f64>() * grid.dx;
            let load: f64 = pn[nx * mid..nx * (mid + 1)].iter().sum::<f64>() * grid.dx;
            let carter = -(1.0 - (1.0 - frac) * (1.0 - frac));
            let got = line / (mu * load);
            assert!(
                (got - carter).abs() < 0.01,
                "xi/xi_c {frac}: {got:.4} vs Carter {carter:.4}"
            );
        }
    }
}
