//! Static equilibrium on level, ideal track (or with the rails displaced vertically under the
//! wheels: a twisted track, [`VehicleModel::static_equilibrium_on`]): a linear stiffness solve
//! of the whole vehicle.
//!
//! Unknowns: the small displacements (x, y, z, roll, pitch, yaw) of every body and wheelset,
//! except frozen ones and the wheelsets' spin. Each force element contributes its stiffness at
//! zero deflection (a bushing its K, a table its slope at 0, so a bump stop inside its
//! clearance contributes nothing; a series spring-damper nothing, since its damper relaxes;
//! an anti-roll bar its torsional k). Each wheel rests on the rail through a contact support
//! at its running circle (x of the axle, y = ±b, z = 0): vertical stiffness
//! [`CONTACT_NORMAL_STIFFNESS`] and, to remove the rigid-body modes of free wheelsets,
//! longitudinal and lateral stiffness [`CONTACT_TANGENT_STIFFNESS`]. Gravity acts at every
//! centre of gravity. The wheel load is the compression force of the vertical support, so the
//! loads balance the weight exactly (up to rounding) unless frozen degrees of freedom or
//! elements to the track carry part of it. See `docs/models/vehicle.md`.

use crate::error::VehicleError;
use crate::linalg::{Mat3, cholesky, cholesky_solve};
use crate::model::{DofKind, Endpoint, ForceLaw, Member, VehicleModel};

/// \[N/m\] vertical stiffness of a wheel's contact support in the static solve.
pub const CONTACT_NORMAL_STIFFNESS: f64 = 1e9;
/// \[N/m\] longitudinal and lateral stiffness of a wheel's contact support in the static solve.
pub const CONTACT_TANGENT_STIFFNESS: f64 = 1e8;

/// Passes of the static solve with elements along their lines (their forces from the last
/// pass's solution) before it fails as not settled.
pub const LINE_PASSES: usize = 20;
/// \[rad\] the largest turn of an element along its line in the static solve: its linearised
/// geometric stiffness (−F/L across the line) is good to about θ²/2 of the force, 0.5 %.
pub const LINE_MAX_TURN: f64 = 0.1;

/// The static equilibrium of a vehicle on level track.
#[derive(Debug, Clone, PartialEq)]
pub struct StaticEquilibrium {
    /// \[N\] vertical wheel load Q per wheelset, `[left, right]`, positive in compression.
    pub wheel_loads: Vec<[f64; 2]>,
    /// \[m, m, m, rad, rad, rad\] displacement of each body from its nominal position.
    pub body_displacement: Vec<[f64; 6]>,
    /// \[m, m, m, rad, rad, rad\] displacement of each wheelset (spin always 0).
    pub wheelset_displacement: Vec<[f64; 6]>,
    /// \[N, N, N, N·m, N·m, N·m\] force and moment of each element on its body 2, local axes:
    /// the preload a simulation needs for the nominal geometry to be in equilibrium.
    pub element_force: Vec<[f64; 6]>,
}

impl StaticEquilibrium {
    /// \[N\] sum of all wheel loads.
    pub fn total_wheel_load(&self) -> f64 {
        self.wheel_loads.iter().map(|q| q[0] + q[1]).sum()
    }
}

/// A linear map from the 6·N displacements to the 6 local deflections of a connection.
struct Connection {
    /// 6 × 6N, row-major.
    g: Vec<f64>,
}

impl Connection {
    fn new(n: usize) -> Self {
        Connection {
            g: vec![0.0; 6 * 6 * n],
        }
    }

    /// Add `sign` × (local deflection of point `p` on member index `m` with centre `c`).
    fn add(&mut self, n: usize, m: usize, c: [f64; 3], p: [f64; 3], axes: &Mat3, sign: f64) {
        let a = [p[0] - c[0], p[1] - c[1], p[2] - c[2]];
        // d = t + r × a = t + S r with S = [[0, az, -ay], [-az, 0, ax], [ay, -ax, 0]].
        let s = [[0.0, a[2], -a[1]], [-a[2], 0.0, a[0]], [a[1], -a[0], 0.0]];
        let cols = 6 * n;
        for i in 0..3 {
            for j in 0..3 {
                // local_i = Σ_j R[j][i] · global_j
                let r = axes[j][i] * sign;
                self.g[i * cols + 6 * m + j] += r;
                for k in 0..3 {
                    self.g[i * cols + 6 * m + 3 + k] += r * s[j][k];
                }
                self.g[(3 + i) * cols + 6 * m + 3 + j] += r;
            }
        }
    }

    /// K += Gᵀ·diag(k)·G.
    fn assemble(&self, k: &[f64; 6], kk: &mut [f64], cols: usize) {
        for (r, kr) in k.iter().enumerate() {
            if *kr == 0.0 {
                continue;
            }
            let row = &self.g[r * cols..(r + 1) * cols];
            for (i, gi) in row.iter().enumerate() {
                if *gi == 0.0 {
                    continue;
                }
                for (j, gj) in row.iter().enumerate() {
                    kk[i * cols + j] += kr * gi * gj;
                }
            }
        }
    }

    fn apply(&self, u: &[f64], cols: usize) -> [f64; 6] {
        let mut out = [0.0; 6];
        for (r, o) in out.iter_mut().enumerate() {
            *o = (0..cols).map(|j| self.g[r * cols + j] * u[j]).sum();
        }
        out
    }
}

impl VehicleModel {
    /// Static equilibrium on level, ideal track under gravity (linear statics, see
    /// [`crate::statics`]).
    ///
    /// Fails with [`VehicleError::Statics`] when a body is not supported in some direction
    /// (nothing connects it to the wheelsets or the track, and it is not frozen).
    pub fn static_equilibrium(&self) -> Result<StaticEquilibrium, VehicleError> {
        self.static_equilibrium_on(&vec![[0.0; 2]; self.wheelsets.len()])
    }

    /// Static equilibrium on a track whose rails are displaced vertically under the wheels:
    /// `rail_heights[i]` \[m\] is `[left, right]` under wheelset `i`'s running circles (a
    /// twisted track: the left rail `c/2` up and the right `c/2` down for a cross-level `c`).
    /// Each wheel's contact support then starts at that height, so its load follows from the
    /// same linear solve (the wheel-unloading check on a twisted track, EN 14363; a negative
    /// load means the wheel would lift off, where the linear solve no longer holds).
    ///
    /// Fails as [`Self::static_equilibrium`], and with [`VehicleError::Statics`] when
    /// `rail_heights` does not have one entry per wheelset or holds a non-finite value.
    pub fn static_equilibrium_on(
        &self,
        rail_heights: &[[f64; 2]],
    ) -> Result<StaticEquilibrium, VehicleError> {
        let message = if rail_heights.len() != self.wheelsets.len() {
            Some(format!(
                "expected a pair of rail heights for each of the {} wheelsets, found {} pairs",
                self.wheelsets.len(),
                rail_heights.len()
            ))
        } else {
            rail_heights
                .iter()
                .position(|h| !(h[0].is_finite() && h[1].is_finite()))
                .map(|i| {
                    format!(
                        "expected finite rail heights under wheelset '{}', found {:?}",
                        self.wheelsets[i].name, rail_heights[i]
                    )
                })
        };
        if let Some(message) = message {
            return Err(VehicleError::Statics {
                vehicle: self.name.clone(),
                message,
            });
        }
        let nb = self.bodies.len();
        let n = nb + self.wheelsets.len();
        let cols = 6 * n;
        let centre = |m: Member| match m {
            Member::Body(b) => self.bodies[b.index()].position,
            Member::Wheelset(w) => self.wheelsets[w.index()].position,
        };
        let index = |m: Member| match m {
            Member::Body(b) => b.index(),
            Member::Wheelset(w) => nb + w.index(),
        };
        let mut kk = vec![0.0; cols * cols];
        let mut connections = Vec::with_capacity(self.forces.len());
        for f in &self.forces {
            let mut c = Connection::new(n);
            // Body 1's end at body 2's point too: the simulator measures the deflection in body
            // 1's axes from body 2's point and puts body 1's reaction there (a massless element;
            // docs/models/dynamics.md), whose linearisation is body 1's motion at P₂. With P₁
            // here, an element with its own `point2_m` started out of equilibrium.
            // An element along the line between its points (`ForceElement::line`) measures
            // the distance from body 1's own point P₁, in the simulator as here.
            let p1 = if f.line { f.point1 } else { f.point2 };
            if let Endpoint::Member(m) = f.body1 {
                c.add(n, index(m), centre(m), p1, &f.axes, -1.0);
            }
            if let Endpoint::Member(m) = f.body2 {
                c.add(n, index(m), centre(m), f.point2, &f.axes, 1.0);
            }
            let k = linear_stiffness(&f.law);
            c.assemble(&k, &mut kk, cols);
            connections.push((c, k));
        }
        let identity = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        let support_k = [
            CONTACT_TANGENT_STIFFNESS,
            CONTACT_TANGENT_STIFFNESS,
            CONTACT_NORMAL_STIFFNESS,
            0.0,
            0.0,
            0.0,
        ];
        let mut supports = Vec::new();
        for (i, w) in self.wheelsets.iter().enumerate() {
            let b = w.contact_half_distance();
            for side in [1.0, -1.0] {
                let p = [
                    w.position[0],
                    w.position[1] + side * b,
                    w.position[2] - w.nominal_radius,
                ];
                let mut c = Connection::new(n);
                c.add(n, nb + i, w.position, p, &identity, 1.0);
                c.assemble(&support_k, &mut kk, cols);
                supports.push(c);
            }
        }
        // Free unknowns: not frozen, not a wheelset's spin.
        let mut free = Vec::new();
        for (i, b) in self.bodies.iter().enumerate() {
            for k in DofKind::ALL {
                if !b.frozen[k.index()] {
                    free.push(6 * i + k.index());
                }
            }
        }
        for (i, w) in self.wheelsets.iter().enumerate() {
            for k in DofKind::ALL {
                if !w.frozen[k.index()] && k != DofKind::Pitch {
                    free.push(6 * (nb + i) + k.index());
                }
            }
        }
        let nf = free.len();
        // gravity, and the supports' preload k·h toward a displaced rail (left first, as the
        // supports are built)
        let heights: Vec<f64> = rail_heights.iter().flatten().copied().collect();
        let rhs: Vec<f64> = free
            .iter()
            .map(|&g| {
                let rail: f64 = supports
                    .iter()
                    .zip(&heights)
                    .map(|(c, h)| CONTACT_NORMAL_STIFFNESS * h * c.g[2 * cols + g])
                    .sum();
                if g % 6 == DofKind::Z.index() {
                    let m = g / 6;
                    let mass = if m < nb {
                        self.bodies[m].mass
                    } else {
                        self.wheelsets[m - nb].mass
                    };
                    rail - mass * self.gravity
                } else {
                    rail
                }
            })
            .collect();
        // Solve K u = gravity on the free unknowns; `Err(j)`: no support at free unknown j.
        // `eps` > 0 adds eps times the largest diagonal entry to every diagonal entry.
        let solve = |kk: &[f64], eps: f64| -> Result<Vec<f64>, usize> {
            let mut a = vec![0.0; nf * nf];
            for (i, gi) in free.iter().enumerate() {
                for (j, gj) in free.iter().enumerate() {
                    a[i * nf + j] = kk[gi * cols + gj];
                }
            }
            if eps > 0.0 {
                let big = (0..nf).fold(0.0f64, |m, i| m.max(a[i * nf + i]));
                for i in 0..nf {
                    a[i * nf + i] += eps * big;
                }
            }
            cholesky(&mut a, nf)?;
            let mut x = rhs.clone();
            cholesky_solve(&a, nf, &mut x);
            Ok(x)
        };
        // Elements along the line between their points turn with it: a force F along the line
        // (on body 2, positive pushing it away) adds the geometric stiffness −F/L on the
        // transverse relative motion (a hanger in tension is a pendulum). F comes from the
        // solution, so with such elements the solve is repeated until their forces settle;
        // the first pass, without it, may need a small regularisation to give them a force.
        let lines: Vec<(usize, f64)> = self
            .forces
            .iter()
            .enumerate()
            .filter(|(_, f)| f.line)
            .map(|(i, f)| (i, f.nominal_length()))
            .collect();
        // all 6·N displacements from the free unknowns' solution `x`
        let scatter = |x: &[f64]| {
            let mut u = vec![0.0; cols];
            for (k, g) in free.iter().enumerate() {
                u[*g] = x[k];
            }
            u
        };
        // the forces along the lines at the free unknowns' solution `x`
        let axial = |x: &[f64]| -> Vec<f64> {
            let u = scatter(x);
            lines
                .iter()
                .map(|&(i, _)| {
                    let (c, k) = &connections[i];
                    -k[0] * c.apply(&u, cols)[0]
                })
                .collect()
        };
        // (a line element in compression in the last pass: it takes stiffness away across its
        // line, which the "no support" message names)
        let mut strut = None;
        let fail = |message: String| VehicleError::Statics {
            vehicle: self.name.clone(),
            message,
        };
        let mut result = solve(&kk, 0.0);
        if !lines.is_empty() {
            // the first forces: from the solution, or a regularised one where only the lines'
            // own stiffness would hold a body
            let first = result.clone().or_else(|_| solve(&kk, 1e-9));
            let mut line_force: Vec<f64> = match &first {
                Ok(x) => axial(x),
                Err(_) => vec![0.0; lines.len()],
            };
            // (the largest change of a line's force in the last pass, and the element)
            let mut unsettled = None;
            for _ in 0..LINE_PASSES {
                let mut kg = kk.clone();
                for (&(i, len), &force) in lines.iter().zip(&line_force) {
                    let kt = -force / len;
                    connections[i]
                        .0
                        .assemble(&[0.0, kt, kt, 0.0, 0.0, 0.0], &mut kg, cols);
                }
                result = solve(&kg, 0.0);
                let Ok(x) = &result else { break };
                unsettled = None;
                for ((f, new), &(i, _)) in line_force.iter_mut().zip(axial(x)).zip(&lines) {
                    let change = (new - *f).abs();
                    if change > 1e-9 * (1.0 + new.abs())
                        && unsettled.is_none_or(|(c, _)| change > c)
                    {
                        unsettled = Some((change, i));
                    }
                    *f = new;
                }
                if unsettled.is_none() {
                    break;
                }
            }
            strut = lines
                .iter()
                .zip(&line_force)
                .find(|(_, f)| **f > 0.0)
                .map(|(&(i, _), _)| i);
            if let Ok(x) = &result {
                if let Some((change, i)) = unsettled {
                    return Err(fail(format!(
                        "the forces of the elements along their lines did not settle in {LINE_PASSES} passes of the static solve (element '{}' still changed by {change:.3e} N): their geometric stiffness (-F/L across the line) dominates the support there; stiffen it, or set the element along a fixed direction",
                        self.forces[i].name
                    )));
                }
                // the linearised geometric stiffness holds for small turns of the lines
                let u = scatter(x);
                for &(i, len) in &lines {
                    let d = connections[i].0.apply(&u, cols);
                    let turn = d[1].hypot(d[2]) / len;
                    if turn > LINE_MAX_TURN {
                        return Err(fail(format!(
                            "element '{}' along its line turns by {turn:.3} rad in the static solve (its body 2's point moves {:.1} mm across the line), beyond the {LINE_MAX_TURN} rad for which its linearised geometric stiffness holds: the support across the line is too soft for the load",
                            self.forces[i].name,
                            d[1].hypot(d[2]) * 1e3
                        )));
                    }
                }
            }
        }
        let rhs = match result {
            Ok(x) => x,
            Err(j) => {
                let g = free[j];
                let (m, k) = (g / 6, DofKind::ALL[g % 6]);
                let who = if m < nb {
                    format!(
                        "body '{}' has no support in {}",
                        self.bodies[m].name,
                        k.body_name()
                    )
                } else {
                    format!(
                        "wheelset '{}' has no support in {}",
                        self.wheelsets[m - nb].name,
                        k.wheelset_name()
                    )
                };
                let strut = strut.map_or(String::new(), |i| {
                    format!(
                        " (element '{}' along its line is in compression, which takes stiffness away across its line: -F/L)",
                        self.forces[i].name
                    )
                });
                return Err(fail(format!(
                    "{who}: connect it by force elements with stiffness in that direction, or freeze it{strut}"
                )));
            }
        };
        let u = scatter(&rhs);
        let wheel_loads = supports
            .chunks(2)
            .zip(rail_heights)
            .map(|(pair, h)| {
                let q = |c: &Connection, rail: f64| {
                    -CONTACT_NORMAL_STIFFNESS * (c.apply(&u, cols)[2] - rail)
                };
                [q(&pair[0], h[0]), q(&pair[1], h[1])]
            })
            .collect();
        let element_force = connections
            .iter()
            .map(|(c, k)| {
                let d = c.apply(&u, cols);
                std::array::from_fn(|i| -k[i] * d[i])
            })
            .collect();
        let disp = |m: usize| -> [f64; 6] { std::array::from_fn(|i| u[6 * m + i]) };
        Ok(StaticEquilibrium {
            wheel_loads,
            body_displacement: (0..nb).map(disp).collect(),
            wheelset_displacement: (nb..n).map(disp).collect(),
            element_force,
        })
    }
}

/// \[N/m ×3, N·m/rad ×3\] stiffness of an element at zero deflection, local axes.
fn linear_stiffness(law: &ForceLaw) -> [f64; 6] {
    let mut k = [0.0; 6];
    match law {
        ForceLaw::Bushing { stiffness, .. } => k = *stiffness,
        ForceLaw::Table { axis, table } => k[axis.index()] = table.slope(0.0).max(0.0),
        // dissipative elements start relaxed and carry no static load
        ForceLaw::SeriesSpringDamper { .. }
        | ForceLaw::Damper { .. }
        | ForceLaw::Friction { .. }
        | ForceLaw::PlanarFriction { .. } => {}
        ForceLaw::AntiRollBar { stiffness } => k[3] = *stiffness,
    }
    k
}
