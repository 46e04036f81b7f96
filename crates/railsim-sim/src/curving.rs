//! Steady-state curving: a vehicle run at constant speed from straight track over a transition
//! into a circular curve of a given radius and cant, and the means of its running quantities
//! once it runs steadily in the curve: per wheelset the lateral displacement and the angle of
//! attack, per wheel Y, Q, Y/Q and the wear number Tγ, per axle the track-shift force, and the
//! carbody's lateral reading. This is the curving table of vehicle dynamics (e.g. Iwnicki (ed.),
//! *Handbook of Railway Vehicle Dynamics*, ch. on curving; in a steady state these means are
//! EN 14363's quasi-static Y_qst, Q_qst, which the standard defines as medians over the curve),
//! computed by time integration of the full model
//! ([`steady_curving`]: the run itself shows whether the vehicle settles, `lateral_swing`) or
//! directly as the steady state of the same equations ([`quasi_static_curving`]: Newton on the
//! whole state, 10–30 times faster, for curves that have a steady state and contact forces
//! smooth enough for Newton).
//!
//! The track of a case is the scene's track file with its alignment replaced and its
//! irregularities removed (rail profiles, gauge, inclination, cant base and rail support kept):
//! a tangent that holds the whole vehicle at the start, a clothoid along which curvature and
//! cant grow linearly, and the curve. The rearmost wheelset starts at s = 0; the quantities are
//! averaged over `average` metres once the rearmost wheelset has run `settle` metres in the
//! curve.

use std::path::Path;

use railsim_track::{HARD_MIN_RADIUS_M, TrackModel, TrackSpec};

use faer::linalg::solvers::Solve;
use railsim_contact::ContactModelKind;
use railsim_ode::OdeSystem;
use railsim_ode::linear::jacobian;

use crate::dynamics::Dynamics;
use crate::error::SimError;
use crate::modal::{ModalOptions, difference_steps};
use crate::run::{RunOptions, RunSummary, Sample, Simulation};
use crate::scene::{
    RunLength, STRAIGHT_CURVATURE, Scene, SpeedProfile, extent, required_curve_radius,
};

/// \[m\] straight track ahead of the leading wheelset at the start.
const LEAD_MARGIN: f64 = 5.0;
/// \[m\] track beyond the leading wheelset at the end.
const END_MARGIN: f64 = 10.0;

/// One curve: radius, cant, side and the speed through it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurveCase {
    /// \[m\] radius.
    pub radius: f64,
    /// \[m\] cant (outer rail above the inner one), ≥ 0.
    pub cant: f64,
    /// Whether the curve turns to the left (its centre on the left, seen in the direction of
    /// travel).
    pub left: bool,
    /// \[m/s\] constant speed.
    pub speed: f64,
}

/// \[m\] the distance run (the rearmost wheelset's) at which a case's steady state is solved and
/// reported: halfway through the settling distance, and at least [`STEADY_MARGIN`] into the
/// circular curve, so that no wheelset's frame sits on the transition's end, where the
/// curvature's rate jumps (with `settle` 0 the rearmost wheelset stood exactly there before
/// stop 45, and its forces moved by some 50 N).
fn steady_at(curve_start: f64, run: &CurvingRun) -> f64 {
    curve_start + (0.5 * run.settle).max(STEADY_MARGIN)
}

/// \[m\] the least distance into the circular curve of [`steady_at`] (the curve is at least
/// the vehicle's length and `END_MARGIN` longer than needed, so it still holds the vehicle).
const STEADY_MARGIN: f64 = 1.0;

/// Lengths of a curving run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurvingRun {
    /// \[m\] length of the transition (clothoid, cant ramp).
    pub transition: f64,
    /// \[m\] distance the rearmost wheelset runs in the curve before the averaging starts.
    pub settle: f64,
    /// \[m\] distance over which the means are taken.
    pub average: f64,
}

impl Default for CurvingRun {
    fn default() -> Self {
        CurvingRun {
            transition: 80.0,
            settle: 100.0,
            average: 100.0,
        }
    }
}

/// Means of one wheel over the averaging stretch.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct WheelMeans {
    /// \[N\] lateral force on the rail, toward its field side.
    pub y: f64,
    /// \[N\] vertical force on the rail, downward.
    pub q: f64,
    /// \[-\] the mean of Y/Q.
    pub y_over_q: f64,
    /// \[N\] wear number Tγ, summed over the wheel's patches.
    pub wear: f64,
}

/// Means of one wheelset over the averaging stretch.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct WheelsetMeans {
    /// \[m\] lateral displacement relative to the track centre line, positive to the left.
    pub lateral: f64,
    /// \[rad\] angle of attack (yaw relative to the track), positive nose-left.
    pub angle_of_attack: f64,
    /// Left and right wheel.
    pub wheels: [WheelMeans; 2],
    /// \[N\] track-shift force ΣY, positive toward +y.
    pub sum_y: f64,
    /// \[m\] largest minus smallest lateral displacement during the averaging (0 for a vehicle
    /// that runs steadily).
    pub lateral_swing: f64,
}

/// The result of one curving case.
#[derive(Debug, Clone)]
pub struct SteadyCurving {
    /// The case.
    pub case: CurveCase,
    /// \[m/s²\] uncompensated lateral acceleration in the track plane,
    /// `v² cos φ / R − g sin |φ|` (toward the outside when positive).
    pub uncompensated: f64,
    /// \[m\] the cant deficiency it corresponds to: `a · cant base / g`.
    pub cant_deficiency: f64,
    /// Per wheelset, numbered from the front.
    pub wheelsets: Vec<WheelsetMeans>,
    /// The wheelsets' names in the vehicle file, in the same order.
    pub wheelset_names: Vec<String>,
    /// \[m/s²\] mean lateral reading of an accelerometer at the carbody's first comfort point
    /// (its centre, unless the scene's `[assessment] comfort_points` sets the points; carbody
    /// axes, positive to the left); `None` for a vehicle without rigid bodies.
    pub carbody_lateral: Option<f64>,
    /// Samples averaged (1 for a quasi-static solution).
    pub samples: usize,
    /// How it was found.
    pub solution: CurvingSolution,
}

/// How a curving case was solved.
#[derive(Debug, Clone)]
pub enum CurvingSolution {
    /// By time integration ([`steady_curving`]): the run's summary.
    Run(Box<RunSummary>),
    /// Directly ([`quasi_static_curving`]).
    QuasiStatic {
        /// Newton iterations.
        iterations: usize,
        /// \[-\] the largest scaled residual left (at most 1, [`QuasiStatic`]).
        residual: f64,
        /// \[s\] wall time of the solution.
        wall: f64,
    },
}

/// The scene of a curving case: `scene` with the case's track (the scene's track file with its
/// alignment replaced and its irregularities removed), constant speed, the rearmost wheelset
/// starting at s = 0, no disturbance, assessed at its log rate (the study's means come from
/// the log's samples). Returns the scene and the track position where the curve begins.
pub fn curving_scene(
    scene: &Scene,
    case: &CurveCase,
    run: &CurvingRun,
) -> Result<(Scene, f64), SimError> {
    let bad = |message: String| SimError::Study {
        message: format!("curving study of scene '{}': {message}", scene.name),
    };
    let required = required_curve_radius(&scene.vehicle).max(HARD_MIN_RADIUS_M);
    if !(case.radius.is_finite() && case.radius >= required) {
        return Err(bad(format!(
            "the radius must be at least {:.1} m (the track's lower limit, and what the \
             vehicle's rigid wheelbase needs), found {} m",
            required, case.radius
        )));
    }
    if !(case.cant >= 0.0 && case.cant <= 0.2) {
        return Err(bad(format!(
            "the cant must lie in [0, 200] mm, found {} mm",
            case.cant * 1e3
        )));
    }
    if !(case.speed > 0.0 && case.speed.is_finite()) {
        return Err(bad(format!(
            "the speed must be positive, found {} km/h",
            case.speed * 3.6
        )));
    }
    if !(run.transition > 0.0 && run.settle >= 0.0 && run.average > 0.0) {
        return Err(bad(format!(
            "the transition ({} m) and the averaging length ({} m) must be positive and the \
             settling distance ({} m) not negative",
            run.transition, run.average, run.settle
        )));
    }
    let (_, x_max, x_min) = extent(&scene.vehicle);
    let length = x_max - x_min;
    let lead_in = length + LEAD_MARGIN;
    let curve_start = lead_in + run.transition;
    let curve_len = run.settle + run.average + length + END_MARGIN;
    let track =
        case_track(&scene.track_file, case, lead_in, run.transition, curve_len).map_err(bad)?;
    let mut base = scene.clone();
    base.track = track;
    // (round wheels, as the track is without irregularities: a steady state)
    base.vehicle.make_wheels_round();
    base.start = -x_min;
    let mut study = base.study(
        SpeedProfile::constant(case.speed),
        RunLength::Distance(curve_start + run.settle + run.average),
        0.0,
    )?;
    // (the means come from the log's samples; the assessment is not used)
    study.sample_at_log_rate();
    Ok((study, curve_start))
}

/// The track of a case, from the scene's track file.
fn case_track(
    file: &Path,
    case: &CurveCase,
    lead_in: f64,
    transition: f64,
    curve_len: f64,
) -> Result<TrackModel, String> {
    let side = if case.left { "left" } else { "right" };
    let curve = Some((case.radius, case.cant, side));
    smooth_track(
        file,
        &format!(
            "curving case R = {} m, cant {} mm",
            case.radius,
            case.cant * 1e3
        ),
        &[
            ("tangent", lead_in, None),
            ("clothoid", transition, None),
            ("curve", curve_len, curve),
        ],
    )
}

/// One segment of [`smooth_track`]: type, length \[m\], and for a curve its radius \[m\],
/// cant \[m\] and direction (`"left"` or `"right"`).
pub(crate) type Segment<'a> = (&'a str, f64, Option<(f64, f64, &'a str)>);

/// The track file `file` with its alignment replaced by `segments` and its irregularities
/// removed (rail profiles, gauge, inclination, cant base and rail support kept), named `what`
/// (the file's name is appended).
pub(crate) fn smooth_track(
    file: &Path,
    what: &str,
    segments: &[Segment],
) -> Result<TrackModel, String> {
    let name = file.display().to_string();
    let text = std::fs::read_to_string(file).map_err(|e| format!("cannot read {name}: {e}"))?;
    let mut table: toml::Table = text
        .parse()
        .map_err(|e| format!("{name}: not a TOML table: {e}"))?;
    table.remove("irregularities");
    // (the track's first rails throughout: the smoothed track is another length)
    table.remove("rail_section");
    table.insert(
        "name".into(),
        toml::Value::String(format!("{what} ({name})")),
    );
    let segment = |&(kind, length, curve): &Segment| {
        let mut t = toml::Table::new();
        t.insert("type".into(), toml::Value::String(kind.into()));
        t.insert("length_m".into(), toml::Value::Float(length));
        if let Some((radius, cant, side)) = curve {
            t.insert("radius_m".into(), toml::Value::Float(radius));
            t.insert("cant_mm".into(), toml::Value::Float(cant * 1e3));
            t.insert("direction".into(), toml::Value::String(side.into()));
        }
        toml::Value::Table(t)
    };
    table.insert(
        "segment".into(),
        toml::Value::Array(segments.iter().map(segment).collect()),
    );
    let text = toml::to_string(&table).map_err(|e| format!("{name}: {e}"))?;
    let spec = TrackSpec::from_toml_str(&text, &name).map_err(|e| e.to_string())?;
    TrackModel::compile(&spec, &name).map_err(|e| e.to_string())
}

/// Sums of the curving quantities over samples, per wheelset, and the range of each
/// wheelset's lateral displacement.
#[derive(Default)]
struct Means {
    sums: Vec<WheelsetMeans>,
    ranges: Vec<(f64, f64)>,
    carbody: f64,
    n: usize,
}

impl Means {
    fn add(&mut self, s: &Sample) {
        if self.sums.is_empty() {
            self.sums = vec![WheelsetMeans::default(); s.wheelsets.len()];
            self.ranges = vec![(f64::INFINITY, f64::NEG_INFINITY); s.wheelsets.len()];
        }
        for ((m, w), (r, y)) in self
            .sums
            .iter_mut()
            .zip(&s.wheelsets)
            .zip(self.ranges.iter_mut().zip(&s.lateral))
        {
            m.lateral += y;
            *r = (r.0.min(*y), r.1.max(*y));
            m.angle_of_attack += w.angle_of_attack_rad;
            m.sum_y += w.y_left_n - w.y_right_n;
            let per_wheel = [
                (
                    w.y_left_n,
                    w.q_left_n,
                    w.y_over_q_left,
                    w.wear_number_left_n,
                ),
                (
                    w.y_right_n,
                    w.q_right_n,
                    w.y_over_q_right,
                    w.wear_number_right_n,
                ),
            ];
            for (wm, (y, q, yq, wear)) in m.wheels.iter_mut().zip(per_wheel) {
                wm.y += y;
                wm.q += q;
                wm.y_over_q += yq;
                wm.wear += wear;
            }
        }
        if let Some(c) = s.carbody.first() {
            self.carbody += c[1];
        }
        self.n += 1;
    }

    /// The result of a case from these sums (at least one sample).
    /// `carbody`: whether the samples carry a carbody reading.
    fn result(
        mut self,
        study: &Scene,
        case: &CurveCase,
        at: f64,
        carbody: bool,
        solution: CurvingSolution,
    ) -> SteadyCurving {
        let k = 1.0 / self.n as f64;
        for (m, r) in self.sums.iter_mut().zip(&self.ranges) {
            m.lateral *= k;
            m.angle_of_attack *= k;
            m.sum_y *= k;
            m.lateral_swing = r.1 - r.0;
            for w in &mut m.wheels {
                w.y *= k;
                w.q *= k;
                w.y_over_q *= k;
                w.wear *= k;
            }
        }
        let frame = study.track.frame_at(at);
        let g = study.vehicle.gravity();
        let uncompensated = case.speed * case.speed * frame.curvature.abs() * frame.roll.cos()
            - g * frame.roll.abs().sin();
        SteadyCurving {
            case: *case,
            uncompensated,
            cant_deficiency: uncompensated * study.track.cant_base() / g,
            wheelsets: self.sums,
            wheelset_names: study
                .vehicle
                .wheelsets_from_front()
                .into_iter()
                .map(|i| study.vehicle.wheelsets()[i].name.clone())
                .collect(),
            carbody_lateral: carbody.then_some(self.carbody * k),
            samples: self.n,
            solution,
        }
    }
}

/// Run one curving case of `scene` with `opts` and take the means (module docs).
pub fn steady_curving(
    scene: &Scene,
    case: &CurveCase,
    run: &CurvingRun,
    opts: &RunOptions,
    progress: &mut dyn FnMut(f64, f64),
) -> Result<SteadyCurving, SimError> {
    let (study, curve_start) = curving_scene(scene, case, run)?;
    let from = curve_start + run.settle;
    let mut means = Means::default();
    let mut sim = Simulation::new(&study)?;
    let summary = sim.run(&study, opts, progress, &mut |s: &Sample| {
        // the rearmost wheelset's distance run (it starts at s = 0) at constant speed
        if s.t * case.speed >= from - 1e-9 {
            means.add(s);
        }
    })?;
    if means.n == 0 {
        return Err(SimError::Study {
            message: format!(
                "curving study of scene '{}': no sample in the averaging stretch (log rate {} Hz)",
                scene.name, study.log.rate_hz
            ),
        });
    }
    let carbody = !summary.assessment.comfort.is_empty();
    Ok(means.result(
        &study,
        case,
        steady_at(curve_start, run),
        carbody,
        CurvingSolution::Run(Box::new(summary)),
    ))
}

/// Limits of the quasi-static solution ([`quasi_static_curving`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct QuasiStatic {
    /// Most Newton iterations.
    pub max_iterations: usize,
    /// \[-\] largest generalised force left unbalanced at the solution, as a fraction of the
    /// vehicle's mean static wheel load (N on translations, N·m per metre on rotations).
    pub force_tol: f64,
    /// \[m/s, rad/s\] largest rate of a position, internal or rail state left at the solution.
    pub rate_tol: f64,
}

impl Default for QuasiStatic {
    fn default() -> Self {
        QuasiStatic {
            max_iterations: 40,
            force_tol: 1e-3,
            rate_tol: 1e-6,
        }
    }
}

/// The steady state of a curving case found directly: the state at which the vehicle, carried
/// along the curve at the case's constant speed, has no acceleration relative to its
/// track-following frames, `f(t*, x) = 0` with the right-hand side of a run evaluated where the
/// whole vehicle is in the curve (the rearmost wheelset half the settling distance into it).
/// Newton's method on the whole state (the Jacobian by central differences with the modal
/// analysis' steps, `modal::difference_steps`, faer's LU) with a backtracking line
/// search on the squared norm of the scaled residual, from the run's initial state (centred, on
/// the tangent). When that fails, Newton starts again nearer the solution: with a contact model
/// other than `polach`, from `polach`'s steady state of the case (STRIPES' and FASTSIM's forces
/// are not smooth enough for Newton from afar); otherwise, or if that fails too, by a
/// continuation: curvature and cant raised in steps of a quarter, each solved from the last
/// solution, a step that fails halved. Each row's residual is scaled to a force (member accelerations
/// times mass or inertia, rail accelerations times the rail mass) or taken as a rate, against
/// the limits of `qs`. Same quantities as [`steady_curving`] from one sample at the solution
/// (`lateral_swing` 0). Errors when Newton does not converge (a curve without a steady state, or
/// forces not smooth enough at the steps' scale): the time integration then tells what happens.
pub fn quasi_static_curving(
    scene: &Scene,
    case: &CurveCase,
    run: &CurvingRun,
    qs: &QuasiStatic,
) -> Result<SteadyCurving, SimError> {
    let started = std::time::Instant::now();
    let steady = steady_state(scene, case, run, qs)?;
    let (study, at) = (&steady.study, steady.at);
    let (x, iterations, residual) = (steady.x, steady.iterations, steady.residual);
    let mut sim = steady.sim;
    let sample = sim.sample_at(at / case.speed, &x)?;
    let mut means = Means::default();
    means.add(&sample);
    Ok(means.result(
        study,
        case,
        at,
        !sample.carbody.is_empty(),
        CurvingSolution::QuasiStatic {
            iterations,
            residual,
            wall: started.elapsed().as_secs_f64(),
        },
    ))
}

/// A steady state of a curving case ([`steady_state`]).
pub(crate) struct SteadyState {
    /// The case's scene and its simulation.
    pub study: Scene,
    pub sim: Simulation,
    /// \[m\] the vehicle reference's track position at the solution (in the curve).
    pub at: f64,
    /// The solution, f(at / V, x) = 0.
    pub x: Vec<f64>,
    /// Newton iterations in all (with the continuation's).
    pub iterations: usize,
    /// The largest scaled residual left.
    pub residual: f64,
}

/// The steady state of `case` ([`quasi_static_curving`]): Newton from the centred start, or
/// after a continuation in curvature and cant.
pub(crate) fn steady_state(
    scene: &Scene,
    case: &CurveCase,
    run: &CurvingRun,
    qs: &QuasiStatic,
) -> Result<SteadyState, SimError> {
    let (study, curve_start) = curving_scene(scene, case, run)?;
    let at = steady_at(curve_start, run);
    let sim = Simulation::new(&study)?;
    let fail = |message: String| SimError::Study {
        message: format!(
            "quasi-static curving of scene '{}', R = {} m at {:.1} km/h: {message}{}; the time \
             integration (the default method) shows whether the vehicle settles",
            scene.name,
            case.radius,
            case.speed * 3.6,
            finer_step_hint(scene)
        ),
    };
    let t = at / case.speed;
    let (x, iterations, residual) = match newton_steady(&sim, t, None, qs) {
        Ok(solved) => solved,
        Err(first) => {
            // A start nearer the solution: for a contact model other than `polach`, `polach`'s
            // steady state of the case (smooth forces, and its own continuation); else, or if
            // Newton fails from there too, the continuation in curvature and cant with the model
            // itself.
            let from_polach = (scene.contact.model != ContactModelKind::Polach)
                .then(|| steady_state(&with_polach(scene), case, run, qs).ok())
                .flatten()
                .and_then(|p| {
                    let (x, it, r) = newton_steady(&sim, t, Some(&p.x), qs).ok()?;
                    Some((x, p.iterations + it, r))
                });
            from_polach
                .or_else(|| continuation(scene, case, run, qs, &sim, t))
                .ok_or_else(|| fail(first))?
        }
    };
    Ok(SteadyState {
        study,
        sim,
        at,
        x,
        iterations,
        residual,
    })
}

/// `scene` with the `polach` contact model: smooth forces, from whose steady state Newton
/// reaches that of STRIPES or FASTSIM, which it does not from afar.
fn with_polach(scene: &Scene) -> Scene {
    let mut smooth = scene.clone();
    smooth.contact.model = ContactModelKind::Polach;
    smooth
}

/// The continuation of [`steady_state`]: curvature and cant raised from none to the case's in
/// steps of a quarter, each solved by Newton from the last solution; a step that fails is
/// halved (down to 1/64; the step doubles again, up to a quarter, after a success), and the last
/// one solves the case itself on `sim` at `t`. Returns the solution, the Newton iterations of the
/// steps solved and the largest scaled residual left, or `None` when a step of 1/64 fails.
fn continuation(
    scene: &Scene,
    case: &CurveCase,
    run: &CurvingRun,
    qs: &QuasiStatic,
    sim: &Simulation,
    t: f64,
) -> Option<(Vec<f64>, usize, f64)> {
    const FIRST: f64 = 0.25;
    const SMALLEST: f64 = 1.0 / 64.0;
    let mut x: Option<Vec<f64>> = None;
    let (mut done, mut step, mut total) = (0.0, FIRST, 0);
    loop {
        let f = (done + step).min(1.0);
        let solved = if f >= 1.0 {
            newton_steady(sim, t, x.as_deref(), qs).ok()
        } else {
            let part = CurveCase {
                radius: case.radius / f,
                cant: case.cant * f,
                ..*case
            };
            curving_scene(scene, &part, run)
                .ok()
                .and_then(|(study, c)| {
                    let psim = Simulation::new(&study).ok()?;
                    let tp = steady_at(c, run) / case.speed;
                    newton_steady(&psim, tp, x.as_deref(), qs).ok()
                })
        };
        match solved {
            Some((xk, it, r)) => {
                total += it;
                if f >= 1.0 {
                    return Some((xk, total, r));
                }
                x = Some(xk);
                done = f;
                step = (2.0 * step).min(FIRST);
            }
            None if step > SMALLEST => step *= 0.5,
            None => return None,
        }
    }
}

/// The quasi-static start of `scene` ([`crate::InitialState::QuasiStatic`]), for
/// `Simulation::new`, which passes `sim` with its static equilibrium built (every member on its
/// own frame's centre line, each wheelset settled on its rails): Newton's method on
/// `f(0, x) = 0` from there, as [`quasi_static_curving`] solves a curving case. If that fails,
/// Newton on the scene itself (its own track, rails and irregularities) starts again nearer, as
/// [`steady_state`]'s fallbacks do for a curving case:
/// 1. for a contact model other than `polach`, from `polach`'s quasi-static start of the same
///    scene: STRIPES' and FASTSIM's forces are not smooth enough for Newton from afar, but often
///    are from there (the R = 150 m curve with `stripes`: 5 iterations after `polach`'s 23);
/// 2. in a curve, from the steady state of that curve's curving case (its radius and cant at the
///    vehicle's reference point, the speed at t = 0), reached with the scene's own model by
///    [`steady_state`]'s continuation in curvature and cant (for `polach` after that case's own
///    Newton).
///
/// Until models other than `polach` got step 2 too (with the removal of the `step_mm = 0.5`
/// workaround of `scenes/manchester_in_curve_r300.toml`, after stop 27), the start had only
/// step 1 for them, and that scene (`stripes` at the default 1 mm contact step, R = 300 m,
/// 150 mm cant, 80 km/h) did not start: the direct Newton stalled after 7 iterations at a
/// largest scaled residual of 32.4 (the leading wheelset's lateral row, 1.8 kN against the 55 N
/// tolerance; its vertical row 22.6), and Newton from `polach`'s state after 1 at 29.8 (the
/// same row; vertical 14.0). The steady-curving case of the same curve
/// ([`quasi_static_curving`]) converged at 1 mm not because its equations are smoother (they
/// are the same: `polach`'s start state is that case's `polach` solution, 0 further
/// iterations, and `stripes` stalls from it at the same 29.8) but because [`steady_state`] has
/// a third fallback: `stripes`' own continuation, 10 + 6 + 4 + 5 iterations to a residual of
/// 0.096, from which the scene's Newton needs none. So the strips' piecewise-smooth forces
/// defeat Newton's line search from `polach`'s state, 1.6 kN of lateral force away, but not
/// from the nearer states of the continuation's steps (the likely mechanism, not measured
/// further: the central-difference Jacobian at 1 µm sees the strips' edges, a local slope that
/// misleads over the longer step). At the finer step of [`SMOOTH_STRIPES_STEP`] Newton from
/// `polach`'s state converges (3 iterations, 28 in all), and Newton at 1 mm from that 0.5 mm
/// state takes 1 iteration (residual 0.067): also a way, but at the cost of a second start (29
/// iterations in all), so the continuation, which the curving case already relies on, is the
/// fallback.
///
/// The scene's disturbance of the leading wheelset (`[initial] lateral_offset_mm`, `yaw_mrad`)
/// is then added to its steady position and held there while a last Newton ([`newton_held`])
/// balances the rest of the vehicle about it. Returns the state, the Newton iterations in all
/// and the largest scaled residual left.
pub(crate) fn quasi_static_start(
    sim: &Simulation,
    scene: &Scene,
) -> Result<(Vec<f64>, usize, f64), SimError> {
    let qs = QuasiStatic::default();
    let (mut x, iterations, residual) = steady_start(sim, scene, &qs)?;
    // The scene's disturbance of the leading wheelset, added to its steady lateral position and
    // yaw and held there while the rest of the vehicle balances about it.
    let model = sim.model();
    let lead = model
        .members
        .iter()
        .filter(|m| m.is_wheelset())
        .nth(scene.initial.wheelset.index());
    let mut held = Vec::new();
    if let Some(mm) = lead {
        for (k, d) in [(1, scene.initial.lateral_offset), (5, scene.initial.yaw)] {
            if let (true, Some(p), Some(row)) = (d != 0.0, mm.pos[k], mm.rate[k]) {
                x[p] += d;
                held.push((p, row));
            }
        }
    }
    if held.is_empty() {
        return Ok((x, iterations, residual));
    }
    let (x, more, residual) =
        newton_held(sim, 0.0, Some(&x), &qs, &held).map_err(|e| SimError::Initial {
            message: format!(
                "quasi-static start of scene '{}' at s = {:.2} m: no equilibrium with the leading \
                 wheelset's disturbance ([initial] lateral_offset_mm, yaw_mrad) held: {e}",
                scene.name, scene.start
            ),
        })?;
    Ok((x, iterations + more, residual))
}

/// The steady state of [`quasi_static_start`], without the disturbance.
fn steady_start(
    sim: &Simulation,
    scene: &Scene,
    qs: &QuasiStatic,
) -> Result<(Vec<f64>, usize, f64), SimError> {
    let qs = *qs;
    let direct = match newton_steady(sim, 0.0, None, &qs) {
        Ok(solved) => return Ok(solved),
        Err(e) => e,
    };
    // Newton on the scene itself from a state `x1` found in `before` iterations. A curving
    // case's study has round wheels (`curving_scene`), so its state lacks the rolled-angle lags
    // of the scene's out-of-round wheelsets, which come last in the layout: they start at 0.
    let from = |(mut x1, before): (Vec<f64>, usize)| {
        x1.resize(sim.model().dim(), 0.0);
        newton_steady(sim, 0.0, Some(&x1), &qs)
            .ok()
            .map(|(x, it, r)| (x, before + it, r))
    };
    // 1. For a model other than `polach`, `polach`'s quasi-static state of the scene itself (its
    // own track and irregularities; the smooth forces Newton needs).
    let other = scene.contact.model != ContactModelKind::Polach;
    if other {
        // (undisturbed: the disturbance is added to this scene's own steady state)
        let mut smooth = with_polach(scene);
        smooth.initial.lateral_offset = 0.0;
        smooth.initial.yaw = 0.0;
        let start = Simulation::new(&smooth).ok().map(|p| {
            (
                p.initial_state().to_vec(),
                p.quasi_static_start().map_or(0, |q| q.0),
            )
        });
        if let Some(solved) = start.and_then(from) {
            return Ok(solved);
        }
    }
    // 2. In a curve, the steady state of that curve's curving case (its radius and cant at the
    // vehicle's reference point, the speed at t = 0) approached by the continuation in
    // curvature and cant with the scene's own model: for `polach` after the case's own Newton
    // ([`steady_state`]), for another model directly ([`case_continuation`]: its Newton from
    // afar and from `polach`'s state are what failed above).
    let f = scene.track.frame_at(scene.start);
    let left = f.curvature > 0.0;
    let case = CurveCase {
        radius: 1.0 / f.curvature.abs(),
        // the outer rail's height above the inner one (`TrackFrame::cant` is the left rail's)
        cant: if left { -f.cant } else { f.cant },
        left,
        speed: sim.model().motion(0.0).1,
    };
    let run = CurvingRun::default();
    let nearer = (f.curvature.abs() > STRAIGHT_CURVATURE)
        .then(|| {
            if other {
                case_continuation(scene, &case, &run, &qs)
            } else {
                steady_state(scene, &case, &run, &qs)
                    .ok()
                    .map(|s| (s.x, s.iterations))
            }
        })
        .flatten();
    nearer.and_then(from).ok_or_else(|| SimError::Initial {
        message: format!(
            "quasi-static start of scene '{}' at s = {:.2} m: no steady state found: {direct}{}; \
             start on a tangent instead ([initial] state = \"static\") and let the vehicle run into \
             the curve",
            scene.name,
            scene.start,
            finer_step_hint(scene)
        ),
    })
}

/// The steady state of `case` approached by [`continuation`] alone, with `scene`'s own contact
/// model, on the case's own study: the state and the Newton iterations of its steps, or `None`.
fn case_continuation(
    scene: &Scene,
    case: &CurveCase,
    run: &CurvingRun,
    qs: &QuasiStatic,
) -> Option<(Vec<f64>, usize)> {
    let (study, curve_start) = curving_scene(scene, case, run).ok()?;
    let sim = Simulation::new(&study).ok()?;
    let t = steady_at(curve_start, run) / case.speed;
    continuation(scene, case, run, qs, &sim, t).map(|(x, it, _)| (x, it))
}

/// \[m\] the contact step at and below which STRIPES' forces are smooth enough for Newton in
/// flange contact from `polach`'s steady state (measured before stop 26 on the Manchester
/// vehicle at R = 300 m, 100 mm cant, 80 km/h: 9 iterations at 0.5 mm and 33 at 0.2 mm, where at
/// the default 1 mm the strips left some 250 N of lateral force that no state removed; with the
/// vehicle's loaded geometry that case converges at 1 mm too, in 32 iterations). In stop 27 the
/// quasi-static start of `scenes/manchester_in_curve_r300.toml` (150 mm cant) stalled at 1 mm
/// from `polach`'s state (largest scaled residual 29.8) and converged at 0.5 mm (3 iterations
/// from there); the start now also has the continuation in curvature and cant with
/// `stripes` itself, which reaches that scene's steady state at 1 mm ([`quasi_static_start`]),
/// and the finer step is the error's hint for what still stalls.
const SMOOTH_STRIPES_STEP: f64 = 0.5e-3;

/// For a failed quasi-static solution with `stripes` at a coarser contact step than
/// [`SMOOTH_STRIPES_STEP`]: a hint to refine it; otherwise nothing.
fn finer_step_hint(scene: &Scene) -> String {
    let step = scene.contact.travel.step;
    if scene.contact.model == ContactModelKind::Stripes && step > SMOOTH_STRIPES_STEP {
        format!(
            " (with `stripes` at a contact step of {} mm; [contact] step_mm = {} makes its forces \
             smooth enough for Newton in flange contact)",
            step * 1e3,
            SMOOTH_STRIPES_STEP * 1e3
        )
    } else {
        String::new()
    }
}

/// Newton's method for `f(t, x) = 0` of `sim`'s model from `start` (default: its initial
/// state), [`quasi_static_curving`]: the solution, the iterations taken and the largest scaled
/// residual left; the reason when it fails.
pub(crate) fn newton_steady(
    sim: &Simulation,
    t: f64,
    start: Option<&[f64]>,
    qs: &QuasiStatic,
) -> Result<(Vec<f64>, usize, f64), String> {
    newton_held(sim, t, start, qs, &[])
}

/// `Dynamics` with some positions held where they start: the acceleration row of each
/// (position index, acceleration row, value) is replaced by the position's distance from its
/// value, so that Newton keeps it there and balances the rest of the state around it.
struct Held<'a> {
    sys: Dynamics<'a>,
    held: Vec<(usize, usize, f64)>,
}

impl OdeSystem for Held<'_> {
    fn dim(&self) -> usize {
        self.sys.dim()
    }

    fn rhs(&mut self, t: f64, x: &[f64], dx: &mut [f64]) -> Result<(), railsim_ode::RhsError> {
        self.sys.rhs(t, x, dx)?;
        for &(p, row, v) in &self.held {
            dx[row] = x[p] - v;
        }
        Ok(())
    }

    /// The model's: a held row (a member's acceleration) depends on a position of the same
    /// member, inside the member's own block.
    fn jacobian_pattern(&self) -> Option<railsim_ode::JacobianPattern> {
        self.sys.jacobian_pattern()
    }
}

/// [`newton_steady`] with the positions `held` (position index, index of its acceleration row)
/// kept at their values in the start state (to 1e-6 m or rad): the equilibrium of the rest of
/// the state about a displaced degree of freedom, as a disturbance held by an external force.
fn newton_held(
    sim: &Simulation,
    t: f64,
    start: Option<&[f64]>,
    qs: &QuasiStatic,
    held: &[(usize, usize)],
) -> Result<(Vec<f64>, usize, f64), String> {
    let model = sim.model();
    let n = model.dim();
    // Row scales: a residual times its scale, over its limit, must be at most 1.
    let q0 = {
        let loads = sim.static_loads();
        loads.iter().map(|q| q[0] + q[1]).sum::<f64>() / (2.0 * loads.len().max(1) as f64)
    };
    let mut scale = vec![1.0 / qs.rate_tol; n];
    for mm in &model.members {
        for k in 0..6 {
            if let Some(i) = mm.rate[k] {
                let m = if k < 3 {
                    mm.mass
                } else {
                    mm.inertia[k - 3][k - 3]
                };
                scale[i] = m / (qs.force_tol * q0);
            }
        }
    }
    if let Some(support) = model.rail_support {
        for w in &model.wheels {
            if let Some(r) = w.rail {
                for i in [r + 2, r + 3] {
                    scale[i] = support.mass / (qs.force_tol * q0);
                }
            }
        }
    }
    // The rolled-angle lags of out-of-round wheelsets grow while the wheels roll on radii other
    // than r0 (`MemberModel::rolled_angle`): no steady state has them still, so they are held
    // where they start, as the defects' positions of the state sought (below).
    let angles: Vec<usize> = model
        .members
        .iter()
        .filter_map(|mm| mm.rolled_angle)
        .collect();
    // a held position's row: its distance from where it is held, to the rate tolerance's
    // number in metres or radians
    for &row in held.iter().map(|h| &h.1).chain(&angles) {
        scale[row] = 1.0 / qs.rate_tol;
    }
    // the convergence test: the largest scaled residual and its row
    let measure = |f: &[f64]| -> (f64, usize) {
        f.iter()
            .zip(&scale)
            .enumerate()
            .fold((0.0, 0), |b, (i, (v, s))| {
                let r = v.abs() * s;
                if r > b.0 { (r, i) } else { b }
            })
    };
    // the line search's merit: the scaled residual's squared norm, along which the Newton step
    // descends whatever the scales (d/dλ |W f|² = −2 |W f|² at λ = 0), unlike the largest
    let merit = |f: &[f64]| -> f64 { f.iter().zip(&scale).map(|(v, s)| (v * s).powi(2)).sum() };
    let steps = difference_steps(model, sim.initial_state(), &ModalOptions::default());
    let mut x = start.unwrap_or(sim.initial_state()).to_vec();
    let mut sys = Held {
        sys: Dynamics::new(model),
        held: held
            .iter()
            .map(|&(p, row)| (p, row, x[p]))
            .chain(angles.iter().map(|&i| (i, i, x[i])))
            .collect(),
    };
    let mut f = vec![0.0; n];
    sys.rhs(t, &x, &mut f).map_err(|e| e.0)?;
    let (mut r, mut worst) = measure(&f);
    let mut iterations = 0;
    let mut xt = vec![0.0; n];
    let mut last_lu = None;
    while r > 1.0 {
        if iterations == qs.max_iterations {
            return Err(format!(
                "Newton did not converge in {iterations} iterations (largest scaled residual {r:.3} at '{}')",
                model.state_names[worst]
            ));
        }
        iterations += 1;
        let jac = jacobian(&mut sys, t, &x, &steps).map_err(|e| e.0)?;
        let lu = jac.partial_piv_lu();
        let dx = lu.solve(faer::Mat::<f64>::from_fn(n, 1, |i, _| -f[i]));
        last_lu = Some(lu);
        if (0..n).any(|i| !dx[(i, 0)].is_finite()) {
            return Err(
                "the Jacobian is singular (a degree of freedom without stiffness or damping)"
                    .to_owned(),
            );
        }
        // Backtracking (Armijo) on the merit: step lengths 1, 1/2, ... 1/1024.
        let m0 = merit(&f);
        let mut lambda = 1.0;
        loop {
            for i in 0..n {
                xt[i] = x[i] + lambda * dx[(i, 0)];
            }
            if sys.rhs(t, &xt, &mut f).is_ok() && merit(&f) <= (1.0 - 1e-4 * lambda) * m0 {
                break;
            }
            lambda *= 0.5;
            if lambda < 1.0 / 1024.0 {
                return Err(format!(
                    "Newton's line search failed after {iterations} iterations (largest scaled residual {r:.3} at '{}'): no steady state near, or contact forces not smooth enough for Newton (STRIPES' strips, FASTSIM's cells; `polach` is smooth)",
                    model.state_names[worst]
                ));
            }
        }
        (r, worst) = measure(&f);
        std::mem::swap(&mut x, &mut xt);
    }
    // Converged to the tolerance, possibly just: one more step with the last Jacobian (no new
    // one; kept only if it lowers the largest residual) takes the typical residual well below
    // it, so that a run started here does not drift by what the tolerance allows.
    // (`f` holds the residual at `x`: the line search's last, accepted evaluation)
    if let Some(lu) = last_lu {
        let dx = lu.solve(faer::Mat::<f64>::from_fn(n, 1, |i, _| -f[i]));
        for i in 0..n {
            xt[i] = x[i] + dx[(i, 0)];
        }
        if (0..n).all(|i| xt[i].is_finite()) && sys.rhs(t, &xt, &mut f).is_ok() {
            let (r1, _) = measure(&f);
            if r1 < r {
                r = r1;
                std::mem::swap(&mut x, &mut xt);
            }
        }
    }
    Ok((x, iterations, r))
}
