//! Boundary-element solver for the frictionless normal contact of two elastic half-spaces:
//! Boussinesq–Love influence coefficients (Love 1929), FFT convolution (DC-FFT, Liu, Wang &
//! Liu 2000) and Polonsky & Keer's (1999) constrained conjugate gradients.
//!
//! This is the reference that the fast normal models are measured against (Kalker's NORM
//! problem, as in CONTACT). Quasi-identical materials are assumed (no normal–tangential
//! coupling).

use std::f64::consts::PI;
use std::sync::Arc;

use rustfft::num_complex::Complex;
use rustfft::{Fft, FftPlanner};

use crate::error::{ElasticError, finite, non_negative, positive};
use crate::material::Material;

/// A uniform rectangular grid of cells in the contact plane.
///
/// Cell `(ix, iy)` has centre `(x0 + ix dx, y0 + iy dy)` and row-major index `ix + nx iy`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grid {
    /// number of cells along x
    pub nx: usize,
    /// number of cells along y
    pub ny: usize,
    /// \[m\] cell size along x
    pub dx: f64,
    /// \[m\] cell size along y
    pub dy: f64,
    /// \[m\] x of the centre of cell (0,0)
    pub x0: f64,
    /// \[m\] y of the centre of cell (0,0)
    pub y0: f64,
}

impl Grid {
    /// A grid of `nx` x `ny` cells covering the rectangle `[x_min, x_max] x [y_min, y_max]` \[m\].
    pub fn covering(
        nx: usize,
        ny: usize,
        x_min: f64,
        x_max: f64,
        y_min: f64,
        y_max: f64,
    ) -> Result<Self, ElasticError> {
        let g = Self {
            nx,
            ny,
            dx: (x_max - x_min) / nx.max(1) as f64,
            dy: (y_max - y_min) / ny.max(1) as f64,
            x0: 0.0,
            y0: 0.0,
        };
        let g = Self {
            x0: x_min + 0.5 * g.dx,
            y0: y_min + 0.5 * g.dy,
            ..g
        };
        g.check()?;
        Ok(g)
    }

    /// Number of cells.
    pub fn len(&self) -> usize {
        self.nx * self.ny
    }

    /// Whether the grid has no cells.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// \[m\] x of the centre of column `ix`.
    pub fn x(&self, ix: usize) -> f64 {
        self.x0 + ix as f64 * self.dx
    }

    /// \[m\] y of the centre of row `iy`.
    pub fn y(&self, iy: usize) -> f64 {
        self.y0 + iy as f64 * self.dy
    }

    /// [m^2] area of one cell.
    pub fn cell_area(&self) -> f64 {
        self.dx * self.dy
    }

    pub(crate) fn check(&self) -> Result<(), ElasticError> {
        for (name, n) in [("grid.nx", self.nx), ("grid.ny", self.ny)] {
            if n == 0 || n > 1 << 14 {
                return Err(ElasticError::InvalidSize {
                    name,
                    found: n,
                    expected: "between 1 and 16384 cells".into(),
                });
            }
        }
        positive("grid.dx [m]", self.dx)?;
        positive("grid.dy [m]", self.dy)?;
        finite("grid.x0 [m]", self.x0)?;
        finite("grid.y0 [m]", self.y0)?;
        Ok(())
    }
}

/// `x ln(y + r)` with `r = sqrt(x^2 + y^2)`, computed without cancellation for `y < 0`
/// (there `y + r = x^2/(r - y)`), and 0 for `x = 0` (its limit).
fn x_log(x: f64, y: f64) -> f64 {
    if x == 0.0 {
        return 0.0;
    }
    let r = x.hypot(y);
    if y >= 0.0 {
        x * (y + r).ln()
    } else {
        x * (2.0 * x.abs().ln() - (r - y).ln())
    }
}

/// Love's primitive `F(x,y) = x ln(y + r) + y ln(x + r)`.
fn love_primitive(x: f64, y: f64) -> f64 {
    x_log(x, y) + x_log(y, x)
}

/// [m/Pa] Normal displacement difference at a point due to a unit uniform pressure on a
/// rectangle of size `hx` x `hy` \[m\] whose centre lies at offset (`off_x`, `off_y`) \[m\] from
/// the point (Love 1929; contact-theory note §4.1; CONTACT `elascf_pcwcns`):
///
/// `A = (1-nu)/(pi G) [F(x2,y2) - F(x1,y2) - F(x2,y1) + F(x1,y1)]`, with
/// `x1 = off_x - hx/2`, `x2 = off_x + hx/2` (likewise y) and `F(x,y) = x ln(y+r) + y ln(x+r)`.
/// Both bodies are counted through the combined `G`, `nu`. For a square cell of side `h`
/// the self-coefficient is `4 ln(1+sqrt 2) h (1-nu)/(pi G)`.
///
/// The kernel is even in each coordinate; it is evaluated at `|off_x|, |off_y|`, so
/// `A_IJ = A_JI` holds exactly.
pub fn love_influence(off_x: f64, off_y: f64, hx: f64, hy: f64, mat: &Material) -> f64 {
    let (off_x, off_y) = (off_x.abs(), off_y.abs());
    let x1 = off_x - 0.5 * hx;
    let x2 = off_x + 0.5 * hx;
    let y1 = off_y - 0.5 * hy;
    let y2 = off_y + 0.5 * hy;
    let s = love_primitive(x2, y2) - love_primitive(x1, y2) - love_primitive(x2, y1)
        + love_primitive(x1, y1);
    (1.0 - mat.nu) / (PI * mat.g) * s
}

/// Linear (non-periodic) convolution of cell pressures with the influence kernel by FFT on a
/// zero-padded (2 nx) x (2 ny) array (DC-FFT: Liu, Wang & Liu 2000; Hockney 1970).
struct Convolver {
    nx: usize,
    ny: usize,
    mx: usize,
    my: usize,
    fwd_row: Arc<dyn Fft<f64>>,
    inv_row: Arc<dyn Fft<f64>>,
    fwd_col: Arc<dyn Fft<f64>>,
    inv_col: Arc<dyn Fft<f64>>,
    /// kernel spectrum in column-major layout (index `j + my i`), scaled by 1/(mx my)
    kernel_hat: Vec<Complex<f64>>,
    /// row-major work array (index `i + mx j`)
    buf_a: Vec<Complex<f64>>,
    /// column-major work array (index `j + my i`)
    buf_b: Vec<Complex<f64>>,
    scratch: Vec<Complex<f64>>,
}

impl Convolver {
    fn new(grid: &Grid, mat: &Material) -> Self {
        let (nx, ny) = (grid.nx, grid.ny);
        let (mx, my) = (2 * nx, 2 * ny);
        let mut planner = FftPlanner::<f64>::new();
        let fwd_row = planner.plan_fft_forward(mx);
        let inv_row = planner.plan_fft_inverse(mx);
        let fwd_col = planner.plan_fft_forward(my);
        let inv_col = planner.plan_fft_inverse(my);
        let scratch_len = [&fwd_row, &inv_row, &fwd_col, &inv_col]
            .iter()
            .map(|f| f.get_inplace_scratch_len())
            .max()
            .unwrap_or(0);
        let zero = Complex::new(0.0, 0.0);
        let mut conv = Self {
            nx,
            ny,
            mx,
            my,
            fwd_row,
            inv_row,
            fwd_col,
            inv_col,
            kernel_hat: vec![zero; mx * my],
            buf_a: vec![zero; mx * my],
            buf_b: vec![zero; mx * my],
            scratch: vec![zero; scratch_len],
        };
        // Kernel in wrapped (FFT) order: offsets 0..n-1 first, then -(n-1)..-1; index n unused.
        let offset = |i: usize, n: usize| -> Option<f64> {
            if i < n {
                Some(i as f64)
            } else if i == n {
                None
            } else {
                Some(i as f64 - 2.0 * n as f64)
            }
        };
        for j in 0..my {
            for i in 0..mx {
                let v = match (offset(i, nx), offset(j, ny)) {
                    (Some(di), Some(dj)) => {
                        love_influence(di * grid.dx, dj * grid.dy, grid.dx, grid.dy, mat)
                    }
                    _ => 0.0,
                };
                conv.buf_a[i + mx * j] = Complex::new(v, 0.0);
            }
        }
        conv.fwd_row
            .process_with_scratch(&mut conv.buf_a, &mut conv.scratch);
        transpose(&conv.buf_a, &mut conv.buf_b, mx, my, my);
        conv.fwd_col
            .process_with_scratch(&mut conv.buf_b, &mut conv.scratch);
        let scale = 1.0 / (mx * my) as f64;
        for (k, v) in conv.kernel_hat.iter_mut().zip(&conv.buf_b) {
            *k = v * scale;
        }
        conv
    }

    /// `u = A p` for cell vectors in row-major order (`ix + nx iy`).
    fn apply(&mut self, p: &[f64], u: &mut [f64]) {
        let (nx, ny, mx, my) = (self.nx, self.ny, self.mx, self.my);
        let zero = Complex::new(0.0, 0.0);
        // Only the first ny rows are non-zero: transform those.
        for j in 0..ny {
            let row = &mut self.buf_a[mx * j..mx * (j + 1)];
            for i in 0..nx {
                row[i] = Complex::new(p[i + nx * j], 0.0);
            }
            row[nx..].fill(zero);
        }
        self.fwd_row
            .process_with_scratch(&mut self.buf_a[..mx * ny], &mut self.scratch);
        transpose(&self.buf_a, &mut self.buf_b, mx, my, ny);
        self.fwd_col
            .process_with_scratch(&mut self.buf_b, &mut self.scratch);
        for (b, k) in self.buf_b.iter_mut().zip(&self.kernel_hat) {
            *b *= k;
        }
        self.inv_col
            .process_with_scratch(&mut self.buf_b, &mut self.scratch);
        // Back to row-major, first ny rows only.
        for j in 0..ny {
            for i in 0..mx {
                self.buf_a[i + mx * j] = self.buf_b[j + my * i];
            }
        }
        self.inv_row
            .process_with_scratch(&mut self.buf_a[..mx * ny], &mut self.scratch);
        for j in 0..ny {
            for i in 0..nx {
                u[i + nx * j] = self.buf_a[i + mx * j].re;
            }
        }
    }
}

/// Row-major `a` (`i + mx j`) to column-major `b` (`j + my i`); rows `j >= rows` of `a` are
/// taken as zero.
fn transpose(a: &[Complex<f64>], b: &mut [Complex<f64>], mx: usize, my: usize, rows: usize) {
    let zero = Complex::new(0.0, 0.0);
    for i in 0..mx {
        let col = &mut b[my * i..my * (i + 1)];
        for j in 0..rows {
            col[j] = a[i + mx * j];
        }
        col[rows..].fill(zero);
    }
}

/// Result of a normal-contact solve.
#[derive(Clone, Copy, Debug)]
pub struct NormalSolution {
    /// \[m\] approach (rigid-body interpenetration `delta`)
    pub approach: f64,
    /// \[N\] total normal force
    pub force: f64,
    /// \[Pa\] largest cell pressure
    pub p_max: f64,
    /// number of cells in contact (p > 0)
    pub n_contact: usize,
    /// iterations of the conjugate-gradient loop
    pub iterations: usize,
}

#[derive(Clone, Copy)]
enum Control {
    Force(f64),
    Approach(f64),
}

/// The outcome of a conjugate-gradient step's guards ([`HalfspaceSolver::descent_step`]).
#[derive(Clone, Copy, Debug, PartialEq)]
enum Step {
    /// A descent step `τ` along `t` on the contact set (`t` reset to the steepest-descent
    /// direction where the conjugate one gave no descent step).
    Contact { tau: f64 },
    /// The gradient vanishes on the contact set and no cell outside overlaps: solved.
    Solved,
    /// The gradient vanishes on the contact set but cells outside overlap: a steepest-descent
    /// step `τ` over the contact set and the overlapping cells.
    Grow { tau: f64 },
}

/// Whether cell `i` is in the contact set (`p > 0`), or with `grow` also an overlapping cell
/// (`p = 0`, `g < 0`).
#[inline]
fn member(p: &[f64], g: &[f64], i: usize, grow: bool) -> bool {
    p[i] > 0.0 || (grow && g[i] < 0.0)
}

/// Half-space normal-contact solver on a fixed grid. All buffers (kernel spectrum, FFT plans,
/// work arrays) are allocated in [`HalfspaceSolver::new`]; solves do not allocate.
pub struct HalfspaceSolver {
    grid: Grid,
    conv: Convolver,
    /// \[Pa\] pressures of the last solve
    p: Vec<f64>,
    p_prev: Vec<f64>,
    u: Vec<f64>,
    g: Vec<f64>,
    t: Vec<f64>,
    r: Vec<f64>,
}

impl HalfspaceSolver {
    /// Builds the influence-kernel spectrum and FFT plans for `grid` and material `mat`.
    pub fn new(grid: Grid, mat: &Material) -> Result<Self, ElasticError> {
        grid.check()?;
        let n = grid.len();
        Ok(Self {
            grid,
            conv: Convolver::new(&grid, mat),
            p: vec![0.0; n],
            p_prev: vec![0.0; n],
            u: vec![0.0; n],
            g: vec![0.0; n],
            t: vec![0.0; n],
            r: vec![0.0; n],
        })
    }

    /// The grid.
    pub fn grid(&self) -> &Grid {
        &self.grid
    }

    /// \[Pa\] pressures of the last solve, row-major (`ix + nx iy`).
    pub fn pressure(&self) -> &[f64] {
        &self.p
    }

    /// Normal displacement difference `u = A p` \[m\] for cell pressures `p` \[Pa\] (row-major),
    /// by FFT convolution.
    pub fn displacement(&mut self, p: &[f64], u: &mut [f64]) -> Result<(), ElasticError> {
        self.check_len("p.len()", p.len())?;
        self.check_len("u.len()", u.len())?;
        for &v in p {
            finite("p [Pa]", v)?;
        }
        self.conv.apply(p, u);
        Ok(())
    }

    fn check_len(&self, name: &'static str, len: usize) -> Result<(), ElasticError> {
        if len == self.grid.len() {
            Ok(())
        } else {
            Err(ElasticError::InvalidSize {
                name,
                found: len,
                expected: format!(
                    "{} cells ({} x {})",
                    self.grid.len(),
                    self.grid.nx,
                    self.grid.ny
                ),
            })
        }
    }

    fn check_common(&self, gap: &[f64], tol: f64, max_iter: usize) -> Result<(), ElasticError> {
        self.check_len("gap.len()", gap.len())?;
        for &h in gap {
            finite("gap [m]", h)?;
        }
        positive("tol [-]", tol)?;
        if max_iter == 0 {
            return Err(ElasticError::InvalidSize {
                name: "max_iter",
                found: 0,
                expected: "at least 1 iteration".into(),
            });
        }
        Ok(())
    }

    /// Pressures for a prescribed total force `force` \[N\] >= 0 on the undeformed gap `gap`
    /// (h_I \[m\] at each cell centre, row-major `ix + nx iy`).
    ///
    /// The solution satisfies `e = h - approach + u >= 0`, `p >= 0`, `p e = 0` with
    /// `u = A p` and `dx dy sum p = force`. Polonsky & Keer (1999) constrained conjugate
    /// gradients: the mean gap over the contact set plays the role of the approach, and the
    /// pressure is rescaled to the force every iteration. Stops when the relative L1 change
    /// of the pressure, `sum|p - p_prev| / sum p`, is below `tol`; the approach is then the
    /// mean of `h + u` over the contact cells. The previous solution, if any, is the start.
    pub fn solve_force(
        &mut self,
        gap: &[f64],
        force: f64,
        tol: f64,
        max_iter: usize,
    ) -> Result<NormalSolution, ElasticError> {
        self.check_common(gap, tol, max_iter)?;
        non_negative("force [N]", force)?;
        if force == 0.0 {
            return Ok(self.unloaded(gap));
        }
        let area = self.grid.cell_area();
        let sum: f64 = self.p.iter().sum();
        if !(sum > 0.0 && sum.is_finite()) {
            let v = force / (area * self.p.len() as f64);
            self.p.fill(v);
        } else {
            let s = force / (area * sum);
            self.p.iter_mut().for_each(|p| *p *= s);
        }
        self.iterate(gap, Control::Force(force), tol, max_iter)
    }

    /// Pressures for a prescribed approach `approach` \[m\] on the undeformed gap `gap`.
    ///
    /// Polonsky & Keer's (1999) constrained conjugate gradients for the displacement-controlled
    /// problem (gradient `h - approach + A p`, no mean shift, no rescaling). Started from the
    /// rigid interpenetration `max(0, approach - h)` scaled by its least-squares fit. Same
    /// stopping rule as [`HalfspaceSolver::solve_force`]. If the surfaces do not touch
    /// (`approach <= min h`) the force is zero.
    pub fn solve_approach(
        &mut self,
        gap: &[f64],
        approach: f64,
        tol: f64,
        max_iter: usize,
    ) -> Result<NormalSolution, ElasticError> {
        self.check_common(gap, tol, max_iter)?;
        finite("approach [m]", approach)?;
        let h_min = gap.iter().copied().fold(f64::INFINITY, f64::min);
        if approach <= h_min {
            self.p.fill(0.0);
            return Ok(NormalSolution {
                approach,
                force: 0.0,
                p_max: 0.0,
                n_contact: 0,
                iterations: 0,
            });
        }
        // Start: p0 = s max(0, delta - h) with s fitting A p0 to delta - h in least squares.
        for (p, &h) in self.p.iter_mut().zip(gap) {
            *p = (approach - h).max(0.0);
        }
        self.conv.apply(&self.p, &mut self.u);
        let (mut num, mut den) = (0.0, 0.0);
        for i in 0..self.p.len() {
            if self.p[i] > 0.0 {
                num += self.u[i] * self.p[i];
                den += self.u[i] * self.u[i];
            }
        }
        let s = if den > 0.0 { num / den } else { 0.0 };
        self.p.iter_mut().for_each(|p| *p *= s);
        self.iterate(gap, Control::Approach(approach), tol, max_iter)
    }

    fn unloaded(&mut self, gap: &[f64]) -> NormalSolution {
        self.p.fill(0.0);
        NormalSolution {
            approach: gap.iter().copied().fold(f64::INFINITY, f64::min),
            force: 0.0,
            p_max: 0.0,
            n_contact: 0,
            iterations: 0,
        }
    }

    /// The constrained conjugate-gradient loop of Polonsky & Keer (1999), steps (a)–(h) of the
    /// contact-theory note §4.2, with `e = h - delta + u` as the gradient.
    fn iterate(
        &mut self,
        gap: &[f64],
        control: Control,
        tol: f64,
        max_iter: usize,
    ) -> Result<NormalSolution, ElasticError> {
        let n = self.p.len();
        let area = self.grid.cell_area();
        let mut g_old = 1.0;
        let mut conjugate = false;
        let mut change = f64::INFINITY;
        for it in 1..=max_iter {
            // (a) u = A p, gap with the current approach.
            self.conv.apply(&self.p, &mut self.u);
            let shift = match control {
                Control::Approach(d) => d,
                Control::Force(_) => {
                    let (mut s, mut c) = (0.0, 0usize);
                    for i in 0..n {
                        if self.p[i] > 0.0 {
                            s += self.u[i] + gap[i];
                            c += 1;
                        }
                    }
                    if c > 0 { s / c as f64 } else { 0.0 }
                }
            };
            // (b), (c) gradient and conjugate direction on the contact set.
            let mut g_norm = 0.0;
            for i in 0..n {
                self.g[i] = self.u[i] + gap[i] - shift;
                if self.p[i] > 0.0 {
                    g_norm += self.g[i] * self.g[i];
                }
            }
            let beta = if conjugate { g_norm / g_old } else { 0.0 };
            for i in 0..n {
                self.t[i] = if self.p[i] > 0.0 {
                    self.g[i] + beta * self.t[i]
                } else {
                    0.0
                };
            }
            g_old = g_norm;
            // (d), (e) r = A t and the step length, with the guards of `descent_step`.
            let (tau, grow) = match self.descent_step(control, beta != 0.0, it)? {
                Step::Solved => return Ok(self.finish(gap, control, it)),
                Step::Contact { tau } => (tau, false),
                Step::Grow { tau } => (tau, true),
            };
            // (e), (f) update, projection, and re-entry of overlapping cells.
            self.p_prev.copy_from_slice(&self.p);
            for i in 0..n {
                if member(&self.p, &self.g, i, grow) {
                    self.p[i] = (self.p[i] - tau * self.t[i]).max(0.0);
                }
            }
            // (a step over the grown set has moved its overlapping cells already)
            conjugate = !grow;
            if !grow {
                for i in 0..n {
                    if self.p[i] == 0.0 && self.g[i] < 0.0 {
                        self.p[i] = -tau * self.g[i];
                        conjugate = false;
                    }
                }
            }
            // (g) force balance.
            let mut sum: f64 = self.p.iter().sum();
            if let Control::Force(f) = control {
                if sum > 0.0 {
                    let s = f / (area * sum);
                    self.p.iter_mut().for_each(|p| *p *= s);
                    sum = f / area;
                } else {
                    // Lost the contact set entirely: restart from a uniform pressure.
                    self.p.fill(f / (area * n as f64));
                    sum = f / area;
                    conjugate = false;
                }
            }
            // (h) convergence on the relative change of the pressure.
            let diff: f64 = self
                .p
                .iter()
                .zip(&self.p_prev)
                .map(|(a, b)| (a - b).abs())
                .sum();
            // (no pressure left under displacement control is no solution: the approach exceeds
            // the smallest gap, so a cell overlaps and the next step's guards grow the set)
            change = if sum > 0.0 { diff / sum } else { f64::INFINITY };
            if change.is_nan() {
                break;
            }
            if change < tol {
                return Ok(self.finish(gap, control, it));
            }
        }
        Err(ElasticError::NotConverged {
            solver: "Polonsky-Keer CG",
            iterations: max_iter,
            residual: change,
            tol,
        })
    }

    /// Steps (d) and (e) of the loop for the direction in `t` (zero outside the contact set):
    /// `r = A t`, for force control less its mean over the set, and the step length
    /// `τ = Σ g t / Σ r t` over the set (Polonsky & Keer 1999). `None` unless the denominator
    /// is positive and `τ` finite and non-zero: a zero step changes no pressure, so the loop's
    /// stopping rule would take it for convergence.
    ///
    /// With `grow` the set is the contact set and the overlapping cells (`p = 0`, `g < 0`).
    fn step_length(&mut self, control: Control, grow: bool) -> (Option<f64>, f64) {
        let n = self.p.len();
        self.conv.apply(&self.t, &mut self.r);
        if let Control::Force(_) = control {
            let (mut s, mut c) = (0.0, 0usize);
            for i in 0..n {
                if member(&self.p, &self.g, i, grow) {
                    s += self.r[i];
                    c += 1;
                }
            }
            let mean = if c > 0 { s / c as f64 } else { 0.0 };
            self.r.iter_mut().for_each(|r| *r -= mean);
        }
        let (mut gt, mut rt) = (0.0, 0.0);
        for i in 0..n {
            if member(&self.p, &self.g, i, grow) {
                gt += self.g[i] * self.t[i];
                rt += self.r[i] * self.t[i];
            }
        }
        let tau = gt / rt;
        let ok = rt > 0.0 && tau.is_finite() && tau != 0.0;
        (ok.then_some(tau), rt)
    }

    /// Steps (d) and (e) with guards against a step that is not a descent step.
    ///
    /// Why the denominator `D = Σ t (r − r̄)` over the contact set `I` can fail to be positive:
    /// with `m` the mean of `t` over `I` and `t' = t − m` (zero mean), `Σ (r − r̄) = 0` gives
    /// `D = t'ᵀ A t = t'ᵀ A t' + m t'ᵀ A 1_I` (displacement control: `D = tᵀ A t`). `A`, the
    /// influence matrix, is symmetric positive definite (the elastic energy `½ pᵀ A p > 0`), so
    /// `D > 0` whenever `t` is non-zero and of zero mean. The gradient `g` has zero mean over
    /// `I` by construction (the approach is the mean gap), but the previous direction had zero
    /// mean over the previous set: when cells left the set and the direction was kept conjugate
    /// (Polonsky & Keer reset it only when cells re-enter), `m ≠ 0` and `D` may be of either
    /// sign even in exact arithmetic; round-off adds to it. And where `g` vanishes on `I` (a
    /// one-cell contact set under force control: `g = 0` identically) `t = 0` and `D = 0`.
    ///
    /// Remedies: a conjugate direction without a descent step is restarted from the
    /// steepest-descent direction `t = g` (the standard restart of nonlinear conjugate
    /// gradients; Nocedal & Wright, Numerical Optimization, 2nd ed. 2006, §5.2), whose `D =
    /// gᵀ A g > 0` unless `g = 0` on `I`. Then the contact set is in equilibrium: solved if no
    /// cell outside overlaps, otherwise the set must grow but Polonsky & Keer's re-entry
    /// `p = −τ g` has no step; the steepest-descent step is taken over the contact set and the
    /// overlapping cells together (`t = g` less its mean over them for force control, so that
    /// `D = tᵀ A t > 0` and `Σ g t = Σ t² > 0`). A step that still fails (only by overflow or
    /// round-off) is [`ElasticError::StepBreakdown`], and so is a non-finite gradient.
    fn descent_step(
        &mut self,
        control: Control,
        conjugate: bool,
        iteration: usize,
    ) -> Result<Step, ElasticError> {
        let n = self.p.len();
        let (tau, _) = self.step_length(control, false);
        if let Some(tau) = tau {
            return Ok(Step::Contact { tau });
        }
        if conjugate {
            for i in 0..n {
                self.t[i] = if self.p[i] > 0.0 { self.g[i] } else { 0.0 };
            }
            if let (Some(tau), _) = self.step_length(control, false) {
                return Ok(Step::Contact { tau });
            }
        }
        let breakdown = |denominator: f64| ElasticError::StepBreakdown {
            solver: "Polonsky-Keer CG",
            iteration,
            denominator,
        };
        if self.g.iter().any(|g| !g.is_finite()) {
            return Err(breakdown(f64::NAN));
        }
        if !(0..n).any(|i| self.p[i] == 0.0 && self.g[i] < 0.0) {
            return Ok(Step::Solved);
        }
        let mean = match control {
            Control::Approach(_) => 0.0,
            Control::Force(_) => {
                let (mut s, mut c) = (0.0, 0usize);
                for i in 0..n {
                    if member(&self.p, &self.g, i, true) {
                        s += self.g[i];
                        c += 1;
                    }
                }
                s / c as f64
            }
        };
        for i in 0..n {
            self.t[i] = if member(&self.p, &self.g, i, true) {
                self.g[i] - mean
            } else {
                0.0
            };
        }
        match self.step_length(control, true) {
            (Some(tau), _) => Ok(Step::Grow { tau }),
            (None, denominator) => Err(breakdown(denominator)),
        }
    }

    fn finish(&mut self, gap: &[f64], control: Control, iterations: usize) -> NormalSolution {
        let area = self.grid.cell_area();
        let force = area * self.p.iter().sum::<f64>();
        let p_max = self.p.iter().copied().fold(0.0, f64::max);
        let n_contact = self.p.iter().filter(|p| **p > 0.0).count();
        let approach = match control {
            Control::Approach(d) => d,
            Control::Force(_) => {
                self.conv.apply(&self.p, &mut self.u);
                let s: f64 = (0..self.p.len())
                    .filter(|&i| self.p[i] > 0.0)
                    .map(|i| self.u[i] + gap[i])
                    .sum();
                s / n_contact.max(1) as f64
            }
        };
        NormalSolution {
            approach,
            force,
            p_max,
            n_contact,
            iterations,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hertz::hertz_from_load;

    fn rel(a: f64, b: f64) -> f64 {
        (a - b).abs() / b.abs()
    }

    fn mat() -> Material {
        Material::new(82e9, 0.28).unwrap()
    }

    fn direct(grid: &Grid, mat: &Material, p: &[f64], u: &mut [f64]) {
        for iy in 0..grid.ny {
            for ix in 0..grid.nx {
                let mut s = 0.0;
                for jy in 0..grid.ny {
                    for jx in 0..grid.nx {
                        let ox = grid.x(jx) - grid.x(ix);
                        let oy = grid.y(jy) - grid.y(iy);
                        s += love_influence(ox, oy, grid.dx, grid.dy, mat) * p[jx + grid.nx * jy];
                    }
                }
                u[ix + grid.nx * iy] = s;
            }
        }
    }

    #[test]
    fn self_coefficient_of_square_cell() {
        let mat = mat();
        for &h in &[1e-4, 2.5e-3] {
            let a = love_influence(0.0, 0.0, h, h, &mat);
            let want = 4.0 * (1.0 + 2f64.sqrt()).ln() * h * (1.0 - mat.nu) / (PI * mat.g);
            assert!(rel(a, want) < 1e-10, "{a} vs {want}");
        }
        // Far field tends to the point-load Boussinesq value (1-nu)/(pi G) hx hy / d.
        let d = 0.5;
        let a = love_influence(d, 0.0, 1e-3, 2e-3, &mat);
        assert!(rel(a, (1.0 - mat.nu) / (PI * mat.g) * 2e-6 / d) < 1e-5);
    }

    #[test]
    fn influence_is_symmetric() {
        let mat = mat();
        let (hx, hy) = (2e-4, 1e-4);
        for &(ox, oy) in &[(0.0, 3e-4), (6e-4, -2e-4), (-1.4e-3, 9e-4), (2e-4, 0.0)] {
            let a = love_influence(ox, oy, hx, hy, &mat);
            // A_IJ = A_JI (offset reversed) and even in each coordinate.
            for (bx, by) in [(-ox, -oy), (-ox, oy), (ox, -oy)] {
                let b = love_influence(bx, by, hx, hy, &mat);
                assert!(rel(b, a) < 1e-13, "({ox},{oy}) vs ({bx},{by}): {a} {b}");
            }
            assert!(a > 0.0);
        }
        // The assembled (FFT) operator is symmetric: q . A p = p . A q.
        let grid = Grid {
            nx: 9,
            ny: 6,
            dx: 2e-4,
            dy: 1e-4,
            x0: 0.0,
            y0: 0.0,
        };
        let mut solver = HalfspaceSolver::new(grid, &mat).unwrap();
        let p: Vec<f64> = (0..grid.len()).map(|i| ((i * 7919) % 13) as f64).collect();
        let q: Vec<f64> = (0..grid.len())
            .map(|i| ((i * 104729) % 17) as f64)
            .collect();
        let (mut ap, mut aq) = (vec![0.0; grid.len()], vec![0.0; grid.len()]);
        solver.displacement(&p, &mut ap).unwrap();
        solver.displacement(&q, &mut aq).unwrap();
        let qap: f64 = q.iter().zip(&ap).map(|(a, b)| a * b).sum();
        let paq: f64 = p.iter().zip(&aq).map(|(a, b)| a * b).sum();
        assert!(rel(qap, paq) < 1e-12);
    }

    #[test]
    fn fft_matvec_equals_direct() {
        let mat = mat();
        let grid = Grid {
            nx: 7,
            ny: 5,
            dx: 3e-4,
            dy: 1.7e-4,
            x0: -1e-3,
            y0: 2e-4,
        };
        let mut solver = HalfspaceSolver::new(grid, &mat).unwrap();
        let mut state: u64 = 12345;
        let p: Vec<f64> = (0..grid.len())
            .map(|_| {
                state = state
                    .wrapping_mul(6_364_136_223_846_793_005)
                    .wrapping_add(1442695040888963407);
                ((state >> 11) as f64 / (1u64 << 53) as f64) * 1e9
            })
            .collect();
        let mut u_fft = vec![0.0; grid.len()];
        let mut u_dir = vec![0.0; grid.len()];
        solver.displacement(&p, &mut u_fft).unwrap();
        direct(&grid, &mat, &p, &mut u_dir);
        let num: f64 = u_fft.iter().zip(&u_dir).map(|(a, b)| (a - b).powi(2)).sum();
        let den: f64 = u_dir.iter().map(|b| b * b).sum();
        let err = (num / den).sqrt();
        let max_err = u_fft
            .iter()
            .zip(&u_dir)
            .map(|(a, b)| rel(*a, *b))
            .fold(0.0, f64::max);
        eprintln!("FFT vs direct mat-vec: relative L2 {err:.1e}, max {max_err:.1e}");
        assert!(err < 1e-10 && max_err < 1e-10);
        assert!(solver.displacement(&p[1..], &mut u_fft).is_err());
    }

    fn ellipse_case(
        a_curv: f64,
        b_curv: f64,
        n: f64,
        cells: usize,
    ) -> (HalfspaceSolver, Vec<f64>, crate::hertz::HertzSolution) {
        let mat = mat();
        let hz = hertz_from_load(a_curv, b_curv, n, &mat).unwrap();
        let (ex, ey) = (1.1 * hz.a, 1.1 * hz.b);
        let grid = Grid::covering(cells, cells, -ex, ex, -ey, ey).unwrap();
        let mut gap = vec![0.0; grid.len()];
        for iy in 0..grid.ny {
            for ix in 0..grid.nx {
                let (x, y) = (grid.x(ix), grid.y(iy));
                gap[ix + grid.nx * iy] = a_curv * x * x + b_curv * y * y;
            }
        }
        (HalfspaceSolver::new(grid, &mat).unwrap(), gap, hz)
    }

    #[test]
    fn hertz_ellipse_contact_fastsim_inp() {
        // a = 8, b = 4 mm, N = 82 kN, G = 82 GPa, nu = 0.28; A = 0.8464e-3, B = 0.2406e-2 1/mm.
        let (mut solver, gap, hz) = ellipse_case(0.8464, 2.406, 82e3, 44);
        let s = solver.solve_force(&gap, 82e3, 1e-10, 500).unwrap();
        let grid = *solver.grid();
        let area = s.n_contact as f64 * grid.cell_area();
        let ab = PI * hz.a * hz.b;
        eprintln!(
            "half-space 44x44: approach {:.5} mm ({:+.2e}), p_max {:.1} MPa ({:+.2e}), \
             area {:+.2e}, {} cells in contact, {} iterations",
            s.approach * 1e3,
            s.approach / 0.09267e-3 - 1.0,
            s.p_max * 1e-6,
            s.p_max / 1223.5e6 - 1.0,
            area / ab - 1.0,
            s.n_contact,
            s.iterations
        );
        assert!(rel(s.approach, 0.09267e-3) < 0.01);
        assert!(rel(s.force, 82e3) < 1e-12);
        assert!(rel(s.p_max, 1223.5e6) < 0.05);
        assert!(rel(area, ab) < 0.05);
        assert!(s.iterations < 200);
        // Complementarity: no interpenetration outside the contact, p >= 0.
        let mut u = vec![0.0; gap.len()];
        let p = solver.pressure().to_vec();
        solver.displacement(&p, &mut u).unwrap();
        for i in 0..gap.len() {
            let e = gap[i] - s.approach + u[i];
            assert!(p[i] >= 0.0);
            assert!(e > -1e-6 * s.approach, "cell {i}: e = {e}");
            if p[i] > 0.0 {
                assert!(e.abs() < 1e-5 * s.approach, "cell {i}: e = {e}");
            }
        }
        // Prescribed approach gives the force back.
        let t = solver.solve_approach(&gap, s.approach, 1e-10, 500).unwrap();
        eprintln!(
            "prescribed approach: force {:+.2e}, {} iterations",
            t.force / 82e3 - 1.0,
            t.iterations
        );
        assert!(rel(t.force, 82e3) < 1e-6, "force {}", t.force);
        assert_eq!(t.n_contact, s.n_contact);
    }

    #[test]
    fn hertz_circle() {
        // A = B = 1/(2R), R = 0.3 m, N = 50 kN.
        let c = 1.0 / 0.6;
        let (mut solver, gap, hz) = ellipse_case(c, c, 50e3, 48);
        let s = solver.solve_force(&gap, 50e3, 1e-10, 500).unwrap();
        let area = s.n_contact as f64 * solver.grid().cell_area();
        eprintln!(
            "half-space circle 48x48: approach {:+.2e}, p_max {:+.2e}, area {:+.2e}",
            s.approach / hz.delta - 1.0,
            s.p_max / hz.p0 - 1.0,
            area / (PI * hz.a * hz.a) - 1.0
        );
        assert!(rel(s.approach, hz.delta) < 0.01);
        assert!(rel(s.p_max, hz.p0) < 0.05);
        assert!(rel(area, PI * hz.a * hz.a) < 0.05);
        // Radial symmetry of the pressure: p(ix, iy) = p(iy, ix).
        let p = solver.pressure();
        let nx = solver.grid().nx;
        for iy in 0..nx {
            for ix in 0..nx {
                let (a, b) = (p[ix + nx * iy], p[iy + nx * ix]);
                assert!((a - b).abs() <= 1e-6 * s.p_max);
            }
        }
    }

    #[test]
    fn degenerate_and_bad_inputs() {
        let mat = mat();
        let grid = Grid::covering(8, 8, -1e-3, 1e-3, -1e-3, 1e-3).unwrap();
        let mut solver = HalfspaceSolver::new(grid, &mat).unwrap();
        let gap: Vec<f64> = (0..64).map(|i| 1e-6 * (i % 8) as f64).collect();
        let s = solver.solve_approach(&gap, -1e-6, 1e-8, 10).unwrap();
        assert_eq!((s.force, s.n_contact), (0.0, 0));
        let s = solver.solve_force(&gap, 0.0, 1e-8, 10).unwrap();
        assert_eq!(s.force, 0.0);
        assert!(solver.solve_force(&gap[1..], 1.0, 1e-8, 10).is_err());
        assert!(solver.solve_force(&gap, f64::NAN, 1e-8, 10).is_err());
        assert!(solver.solve_force(&gap, 1.0, 0.0, 10).is_err());
        let mut bad = gap.clone();
        bad[3] = f64::INFINITY;
        assert!(solver.solve_approach(&bad, 1e-6, 1e-8, 10).is_err());
        let err = solver.solve_force(&gap, 1e3, 1e-15, 1).unwrap_err();
        assert!(matches!(err, ElasticError::NotConverged { .. }));
        assert!(HalfspaceSolver::new(Grid { nx: 0, ..grid }, &mat).is_err());
        assert!(HalfspaceSolver::new(Grid { dx: -1.0, ..grid }, &mat).is_err());
    }

    /// Force control started from a one-cell contact: on a one-cell contact set the gradient
    /// (gap minus its mean over the set) vanishes identically, so the conjugate direction is zero
    /// and so is the step's denominator `tᵀ(A t − mean)`. The step used to be taken as zero, no
    /// overlapping cell re-entered (their pressure `−τ g` is zero too), the pressure did not
    /// change and the solve reported convergence on the old cell while another interpenetrated
    /// by 0.1 mm. Now the contact set grows by a steepest-descent step over it and the
    /// overlapping cells, and the solve finds the new contact.
    #[test]
    fn a_one_cell_start_is_not_taken_for_the_solution() {
        let mat = mat();
        let grid = Grid::covering(8, 8, -1e-3, 1e-3, -1e-3, 1e-3).unwrap();
        let mut solver = HalfspaceSolver::new(grid, &mat).unwrap();
        let (a, b) = (9, 45);
        // a single cell standing out by 1 mm, lightly loaded: it alone carries the load
        let mut gap = vec![1e-3; grid.len()];
        gap[a] = 0.0;
        let s = solver.solve_force(&gap, 10.0, 1e-10, 100).unwrap();
        assert_eq!(s.n_contact, 1);
        assert!(solver.pressure()[a] > 0.0);
        // then another cell stands out 0.1 mm further; the solve starts from the last pressure
        gap[b] = -1e-4;
        let s = solver.solve_force(&gap, 10.0, 1e-10, 100).unwrap();
        let p = solver.pressure().to_vec();
        let mut u = vec![0.0; grid.len()];
        solver.displacement(&p, &mut u).unwrap();
        let e: Vec<f64> = (0..grid.len())
            .map(|i| gap[i] - s.approach + u[i])
            .collect();
        eprintln!(
            "{} iterations, {} cells in contact, p[a] = {:.3e} Pa, p[b] = {:.3e} Pa, \
             e[b] = {:.3e} m",
            s.iterations, s.n_contact, p[a], p[b], e[b]
        );
        assert!(rel(s.force, 10.0) < 1e-12);
        assert_eq!((s.n_contact, p[a]), (1, 0.0));
        for i in 0..grid.len() {
            assert!(p[i] >= 0.0);
            assert!(e[i] > -1e-12, "cell {i} interpenetrates: e = {:e} m", e[i]);
        }
    }

    /// The guard itself, on a crafted direction: all 16 cells in contact, a zero-mean gradient,
    /// and a "conjugate" direction `t = t' + m` whose zero-mean part `t' = e_corner − e_centre`
    /// is swamped by a mean `m` (what a kept conjugate direction carries after cells left the
    /// contact set). Its denominator `t'ᵀ A t' + m t'ᵀ A 1` is negative (a corner cell's row of
    /// `A` sums to less than a centre cell's), so no step is taken along it; the guard restarts
    /// from `t = g` with `τ = gᵀg / gᵀ A g`. A non-finite gradient is a breakdown.
    #[test]
    fn a_conjugate_direction_without_descent_is_restarted() {
        let mat = mat();
        let grid = Grid::covering(4, 4, -1e-3, 1e-3, -1e-3, 1e-3).unwrap();
        let n = grid.len();
        let mut solver = HalfspaceSolver::new(grid, &mat).unwrap();
        let a = |solver: &mut HalfspaceSolver, v: &[f64]| {
            let mut u = vec![0.0; n];
            solver.displacement(v, &mut u).unwrap();
            u
        };
        let dot = |x: &[f64], y: &[f64]| x.iter().zip(y).map(|(a, b)| a * b).sum::<f64>();
        let (corner, centre) = (0, 5);
        let mut tz = vec![0.0; n];
        (tz[corner], tz[centre]) = (1.0, -1.0);
        let (atz, a1) = (a(&mut solver, &tz), a(&mut solver, &vec![1.0; n]));
        let (curv, cross) = (dot(&tz, &atz), dot(&tz, &a1));
        assert!(curv > 0.0 && cross < 0.0, "{curv} {cross}");
        let m = 2.0 * curv / -cross;
        let predicted = curv + m * cross;
        solver.p.fill(1e6);
        let g: Vec<f64> = (0..n).map(|i| 1e-6 * (i as f64 - 7.5)).collect();
        solver.g.copy_from_slice(&g);
        for i in 0..n {
            solver.t[i] = tz[i] + m;
        }
        let (tau, denominator) = solver.step_length(Control::Force(1.0), false);
        eprintln!("crafted direction: denominator {denominator:e} (predicted {predicted:e})");
        assert_eq!(tau, None);
        assert!(denominator < 0.0);
        assert!(
            rel(denominator, predicted) < 1e-9,
            "{denominator} vs {predicted}"
        );
        for i in 0..n {
            solver.t[i] = tz[i] + m;
        }
        let step = solver.descent_step(Control::Force(1.0), true, 3).unwrap();
        assert_eq!(solver.t, g);
        let ag = a(&mut solver, &g);
        let want = dot(&g, &g) / dot(&g, &ag);
        match step {
            Step::Contact { tau } => assert!(rel(tau, want) < 1e-9, "{tau} vs {want}"),
            other => panic!("{other:?}"),
        }
        solver.g[7] = f64::NAN;
        let err = solver
            .descent_step(Control::Force(1.0), true, 3)
            .unwrap_err();
        assert!(
            matches!(err, ElasticError::StepBreakdown { iteration: 3, .. }),
            "{err}"
        );
    }
}
