//! Linear stability and modes of a vehicle running at constant speed on straight, ideal track:
//! the eigenvalue analysis of vehicle dynamics (root locus against speed, the **linear critical
//! speed** where the least damped oscillatory mode loses its damping).
//!
//! The vehicle's equations (`crate::dynamics`, with the scene's contact model evaluated online,
//! as in a run) are linearised about its centred equilibrium at speed V: the static equilibrium
//! with every wheelset settled on its rails, spinning at free rolling ([`Simulation::new`] with
//! no disturbance), on the scene's track file with its alignment replaced by a tangent and its
//! irregularities removed, and each wheelset's spin then set to its rolling equilibrium (with a
//! traction or brake torque, the spin whose creep torque balances it, and then the whole state
//! balanced by Newton, the quasi-static start's, so that the suspension carries the torque's
//! creep forces: [`ModalAnalysis::balance`]). The
//! Jacobian is a central difference of the right-hand side ([`railsim_ode::linear::jacobian`])
//! with steps of 1 µm (1 µrad) on positions and internal states and 10 µm/s (10 µrad/s) on
//! rates, far above the contact search's tolerances and small enough that the creep forces stay
//! linear. The Hertz rungs' forces are smooth at that scale; STRIPES' strips make its forces
//! piecewise smooth, and its linearisation depends on the step (docs/validation.md §11). The
//! motion about the equilibrium is `Σ c_k v_k e^{λ_k t}`; a mode is stable when `Re λ < 0`.
//!
//! A mode is described by its damped frequency `|Im λ|/2π`, its damping ratio `−Re λ/|λ|` and
//! the coordinates it moves most (eigenvector components of the positions, angles counted with
//! a lever of 1 m). The linear critical speed is the lowest speed at which an oscillatory mode
//! (above [`MIN_FREQUENCY`]) has `Re λ ≥ 0`: the Hopf point of the centred running. For a
//! railway vehicle it usually lies above the nonlinear critical speed of
//! [`crate::stability::ramp_down`], because the bifurcation is subcritical (True 2013; Polach
//! 2006): the two methods answer different questions, and the linear one needs a contact that is
//! smooth about the centred position (the conicity at small amplitude decides it).
//!
//! **In a curve** ([`modes_in_curve`]) the linearisation point is the steady curving state of
//! [`crate::curving::quasi_static_curving`] (Newton on the whole state in the circular curve,
//! where the equations no longer depend on the distance run), and the Jacobian is taken there
//! with the same steps: the modes of the vehicle in steady curving, with its wheels off centre,
//! yawed and, in tight curves, in flange contact.
//!
//! Sources: Lyapunov's indirect method and the root locus of railway vehicles as in Wickens,
//! *Fundamentals of Rail Vehicle Dynamics* (2003), ch. 3–4, and Knothe & Stichel, *Rail Vehicle
//! Dynamics* (2017), ch. 8; the eigen decomposition is faer's (Francis QR).

use railsim_ode::OdeSystem;
use railsim_ode::linear::{Eigenpair, eigenpairs, jacobian};

use railsim_log::LogStats;

use crate::curving::{
    CurveCase, CurvingRun, QuasiStatic, SteadyState, newton_steady, smooth_track, steady_state,
};
use crate::dynamics::Dynamics;
use crate::error::SimError;
use crate::model::SimModel;
use crate::run::{Simulation, SpinTarget, settle_spins};
use crate::scene::{RunLength, Scene, SpeedProfile, extent};

/// \[Hz\] modes slower than this are not counted as oscillatory (a real eigenvalue pair may
/// split into a slow complex pair through round-off).
pub const MIN_FREQUENCY: f64 = 0.05;

/// Settings of the linearisation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModalOptions {
    /// \[m, rad\] difference step of positions, internal states and rail displacements.
    pub position_step: f64,
    /// \[m/s, rad/s\] difference step of rates (at least 1e-7 of a large one, e.g. a spin).
    pub rate_step: f64,
}

impl Default for ModalOptions {
    fn default() -> Self {
        ModalOptions {
            position_step: 1e-6,
            rate_step: 1e-5,
        }
    }
}

/// \[m\] track ahead of and behind the vehicle.
const MARGIN: f64 = 10.0;

/// One mode of the linearised vehicle.
#[derive(Debug, Clone, PartialEq)]
pub struct Mode {
    /// \[1/s\] real part of the eigenvalue (growth rate; negative: decaying).
    pub re: f64,
    /// \[rad/s\] imaginary part, ≥ 0 (one of each conjugate pair is kept).
    pub im: f64,
    /// \[Hz\] damped frequency.
    pub frequency: f64,
    /// \[-\] damping ratio `−Re λ / |λ|`.
    pub damping_ratio: f64,
    /// The position coordinates the mode moves most: (state name, magnitude relative to the
    /// largest), at most five, largest first, down to a tenth of the largest.
    pub shape: Vec<(String, f64)>,
    /// The eigenvector over the whole state, `(re, im)` per component, scaled so that its
    /// largest position component (angles with a lever of 1 m) is `1 + 0i`.
    pub vector: Vec<[f64; 2]>,
}

impl Mode {
    /// Whether it is an oscillatory mode (frequency at least [`MIN_FREQUENCY`]).
    pub fn is_oscillatory(&self) -> bool {
        self.frequency >= MIN_FREQUENCY
    }

    /// Whether it is a divergent mode: not oscillatory, growing faster than [`DIVERGENT_RATE`]
    /// (a static instability, which the linear critical speed of hunting does not count).
    pub fn is_divergent(&self) -> bool {
        !self.is_oscillatory() && self.re > DIVERGENT_RATE
    }

    /// \[1/s\] its growth rate for the stability decision: Re λ, or 0 for a neutral mode, whose
    /// |Re λ| is within [`NEUTRAL`] of |λ| (an undamped mode of the model's own physics, such as
    /// a dry-friction element linearised as stuck with nothing else to damp its mass: its real
    /// part is round-off of either sign, which would decide the search by chance).
    pub fn growth(&self) -> f64 {
        if self.re.abs() <= NEUTRAL * self.re.hypot(self.im) {
            0.0
        } else {
            self.re
        }
    }
}

/// \[-\] a mode whose |Re λ| is at most this fraction of |λ| is neutral ([`Mode::growth`]): above
/// the round-off of the difference Jacobian's eigenvalues (the stuck friction of
/// docs/validation.md §12 beside the Wickens wheelset gives Re λ = 0 to the digits printed),
/// far below the damping ratios the search resolves (its bisection ends at a relative speed
/// tolerance, where the hunting mode's ratio is some 1e-4).
pub const NEUTRAL: f64 = 1e-8;

/// \[1/s\] a non-oscillatory mode growing faster than this is divergent ([`Mode::is_divergent`]):
/// an e-folding time of 1000 s, some 28 km at 100 km/h, longer than any run, and far above the
/// round-off of a zero eigenvalue (the free wheelset's longitudinal rigid-body modes in the
/// Klingel scene: |Re λ| below 1e-6/s at 18–300 km/h, `railsim modes --all --csv`). The
/// Manchester vehicle's real modes are all damped, the slowest at −23.5/s.
pub const DIVERGENT_RATE: f64 = 1e-3;

/// The modes of a scene's vehicle at one speed.
#[derive(Debug, Clone)]
pub struct ModalAnalysis {
    /// \[m/s\]
    pub speed: f64,
    /// Every mode (one per real eigenvalue and per conjugate pair), least stable first.
    pub modes: Vec<Mode>,
    /// Number of state variables.
    pub states: usize,
    /// The largest acceleration (or rate of an internal state) at the equilibrium, with its
    /// state's name: how far the linearisation point is from an equilibrium \[m/s², rad/s²\].
    pub residual: (String, f64),
    /// The state linearised about.
    pub equilibrium: Vec<f64>,
    /// On straight track ([`modes_at`]) with a traction or brake torque: the Newton iterations
    /// that balanced the whole state after the spins (0 if it already was), or why Newton
    /// failed (the spins' equilibrium is then linearised about; `residual` shows the rest).
    /// `Ok(0)` without a torque, and in a curve, whose steady state is Newton's already.
    pub balance: Result<usize, String>,
    /// \[s\] the time it was linearised at: 0 on straight track; in a curve the time at which
    /// the case's run (`crate::curving::curving_scene`) is at the steady state, so that
    /// [`Simulation::start_from`] can restart that run there.
    pub time: f64,
}

impl ModalAnalysis {
    /// The least damped oscillatory mode (largest real part), if any.
    pub fn least_stable(&self) -> Option<&Mode> {
        self.modes.iter().find(|m| m.is_oscillatory())
    }

    /// The fastest-growing divergent mode ([`Mode::is_divergent`]), if any.
    pub fn divergent(&self) -> Option<&Mode> {
        self.modes.iter().find(|m| m.is_divergent())
    }
}

/// The scene that [`modes_at`] linearises: `scene` at constant `speed` on its track file with
/// the alignment replaced by a tangent long enough for the vehicle and its irregularities
/// removed, its wheels made round, undisturbed.
pub fn modal_scene(scene: &Scene, speed: f64) -> Result<Scene, SimError> {
    if !(speed.is_finite() && speed > 0.0) {
        return Err(SimError::Study {
            message: format!(
                "modal analysis of scene '{}': the speed must be positive, found {speed} m/s",
                scene.name
            ),
        });
    }
    let (_, x_max, x_min) = extent(&scene.vehicle);
    let length = x_max - x_min + 2.0 * MARGIN + 1.0;
    let track = smooth_track(
        &scene.track_file,
        "straight ideal track of a modal analysis",
        &[("tangent", length, None)],
    )
    .map_err(|message| SimError::Study {
        message: format!("modal analysis of scene '{}': {message}", scene.name),
    })?;
    let mut base = scene.clone();
    base.track = track;
    // (round wheels, as the track is without irregularities: the linearisation of the vehicle)
    base.vehicle.make_wheels_round();
    base.start = MARGIN - x_min;
    base.initial.yaw = 0.0;
    // a run of 0.5 m: the study checks it stays on the track
    base.study(
        SpeedProfile::constant(speed),
        RunLength::Duration(0.5 / speed),
        0.0,
    )
}

/// The modes of `scene`'s vehicle at constant `speed` \[m/s\] (module docs).
pub fn modes_at(scene: &Scene, speed: f64, opts: &ModalOptions) -> Result<ModalAnalysis, SimError> {
    check_steps(scene, opts)?;
    let study = modal_scene(scene, speed)?;
    let sim = Simulation::new(&study)?;
    let model = sim.model();
    let mut x0 = sim.initial_state().to_vec();
    let mut sys = Dynamics::new(model);
    let fail = |what: String| SimError::Study {
        message: format!(
            "modal analysis of scene '{}' at {:.2} km/h: {what}",
            scene.name,
            speed * 3.6
        ),
    };
    // Each wheelset's spin to its rolling equilibrium: [`Simulation::new`] starts it in free
    // rolling (no creep torque about its axle, to 1e-6 rad/s²), which is this equilibrium unless
    // the wheelset has a traction or brake torque, which the spin found here balances by creep.
    // (Until the free-rolling start, `Simulation::new` spun each wheelset at `V / r` with `r`
    // its mean rolling radius, but a wide conformal patch with spin also carries a longitudinal
    // creep force (the contact benchmark's Fx at y = 0.5 mm, docs/validation.md §1), so that
    // the axles started with a small torque: 8.6 rad/s² on the Manchester vehicle.)
    let mut f0 = vec![0.0; x0.len()];
    settle_spins(&mut sys, &mut x0, &mut f0, SpinTarget::Equilibrium).map_err(fail)?;
    // With a traction or brake torque the creep forces that balance it also load the
    // suspension: the whole state is then balanced by Newton, as the quasi-static start's
    // (`curving::newton_steady`). Where it fails (no steady state: a torque with nothing to
    // hold the vehicle's x; or forces not smooth enough for Newton) the spins' equilibrium is
    // kept, and the residual and `balance` tell. Without a torque the state above is the one
    // linearised about, as before (a free wheelset's x has no stiffness, so Newton on it would
    // fail for nothing).
    let driven = scene.vehicle.wheelsets().iter().any(|w| w.torque != 0.0);
    let balance = if driven {
        newton_steady(&sim, 0.0, Some(&x0), &QuasiStatic::default()).and_then(
            |(x, iterations, _)| {
                if iterations > 0 {
                    let mut f = vec![0.0; x.len()];
                    sys.rhs(0.0, &x, &mut f).map_err(|e| e.0)?;
                    (x0, f0) = (x, f);
                }
                Ok(iterations)
            },
        )
    } else {
        Ok(0)
    };
    let mut analysis = linearise(model, &mut sys, 0.0, x0, &f0, speed, opts).map_err(fail)?;
    analysis.balance = balance;
    Ok(analysis)
}

/// Check the difference steps of `opts`: at most 1 mm and 10 mm/s.
fn check_steps(scene: &Scene, opts: &ModalOptions) -> Result<(), SimError> {
    if opts.position_step > 0.0
        && opts.position_step <= 1e-3
        && opts.rate_step > 0.0
        && opts.rate_step <= 1e-2
    {
        return Ok(());
    }
    Err(SimError::Study {
        message: format!(
            "modal analysis of scene '{}': the difference steps must lie in (0, 1] mm and (0, 10] mm/s, found {} mm and {} mm/s",
            scene.name,
            opts.position_step * 1e3,
            opts.rate_step * 1e3
        ),
    })
}

/// The modes of `model`'s equations linearised at `(t, x0)`, where the right-hand side is
/// `f0`, at `speed` \[m/s\].
fn linearise(
    model: &SimModel,
    sys: &mut Dynamics,
    t: f64,
    x0: Vec<f64>,
    f0: &[f64],
    speed: f64,
    opts: &ModalOptions,
) -> Result<ModalAnalysis, String> {
    let n = x0.len();
    // positions' derivatives are the rates; the rest are accelerations and rates of internal
    // and rail states, which vanish at an equilibrium
    let residual = (model.n_pos..n)
        .map(|i| (i, f0[i].abs()))
        .fold(None::<(usize, f64)>, |b, (i, v)| match b {
            Some((_, bv)) if bv >= v => b,
            _ => Some((i, v)),
        })
        .map_or((String::new(), 0.0), |(i, v)| {
            (model.state_names[i].clone(), v)
        });
    let steps = difference_steps(model, &x0, opts);
    let jac = jacobian(sys, t, &x0, &steps).map_err(|e| e.0)?;
    let pairs = eigenpairs(&jac)?;
    let modes = pairs
        .iter()
        .filter(|p| p.im >= 0.0)
        .map(|p| mode(p, &model.state_names[..model.n_pos]))
        .collect();
    Ok(ModalAnalysis {
        speed,
        modes,
        states: n,
        residual,
        equilibrium: x0,
        balance: Ok(0),
        time: t,
    })
}

/// The modes of `scene`'s vehicle in steady curving through `case` (module docs): linearised
/// about the quasi-static solution of [`crate::curving::quasi_static_curving`] (`run`'s lengths
/// place it in the circular curve, `qs` solves it), with `opts`' steps. Needs a contact model
/// smooth enough for Newton (the Hertz rungs; STRIPES stalls in flange contact, as there).
pub fn modes_in_curve(
    scene: &Scene,
    case: &CurveCase,
    run: &CurvingRun,
    qs: &QuasiStatic,
    opts: &ModalOptions,
) -> Result<ModalAnalysis, SimError> {
    check_steps(scene, opts)?;
    let SteadyState { sim, at, x, .. } = steady_state(scene, case, run, qs)?;
    let model = sim.model();
    let t = at / case.speed;
    let mut sys = Dynamics::new(model);
    let fail = |what: String| SimError::Study {
        message: format!(
            "modal analysis of scene '{}' in the curve R = {} m at {:.2} km/h: {what}",
            scene.name,
            case.radius,
            case.speed * 3.6
        ),
    };
    let mut f0 = vec![0.0; x.len()];
    sys.rhs(t, &x, &mut f0).map_err(|e| fail(e.0))?;
    linearise(model, &mut sys, t, x, &f0, case.speed, opts).map_err(fail)
}

/// The difference step of every state of `model` at `x` for a Jacobian: `opts.rate_step` (at
/// least 1e-7 of the value, e.g. of a spin) on rates, member and rail, and `opts.position_step`
/// on positions, internal states and rail displacements.
pub(crate) fn difference_steps(model: &SimModel, x: &[f64], opts: &ModalOptions) -> Vec<f64> {
    let mut steps = vec![opts.position_step; x.len()];
    let rates = (model.n_pos..model.n_pos + model.n_rate).chain(
        model
            .wheels
            .iter()
            .filter_map(|w| w.rail)
            .flat_map(|r| [r + 2, r + 3]),
    );
    for i in rates {
        steps[i] = rate_step(opts.rate_step, x[i]);
    }
    steps
}

/// The difference step of a rate of value `v`: `step`, or 1e-7 of a large value.
fn rate_step(step: f64, v: f64) -> f64 {
    step.max(1e-7 * v.abs())
}

/// A mode from an eigenpair: the positions' components (the first `names.len()`).
fn mode(p: &Eigenpair, names: &[String]) -> Mode {
    let mut parts: Vec<(usize, f64)> = p.vector[..names.len()]
        .iter()
        .map(|c| c[0].hypot(c[1]))
        .enumerate()
        .collect();
    parts.sort_by(|a, b| b.1.total_cmp(&a.1));
    let big = parts.first().map_or(0.0, |q| q.1);
    let shape = parts
        .iter()
        .take(5)
        .filter(|q| big > 0.0 && q.1 >= 0.1 * big)
        .map(|&(i, v)| (names[i].clone(), v / big))
        .collect();
    // scaled to a largest position component of 1 + 0i
    let vector = match parts.first() {
        Some(&(i, m)) if m > 0.0 => {
            let c = p.vector[i];
            let m2 = m * m;
            p.vector
                .iter()
                .map(|v| {
                    [
                        (v[0] * c[0] + v[1] * c[1]) / m2,
                        (v[1] * c[0] - v[0] * c[1]) / m2,
                    ]
                })
                .collect()
        }
        _ => p.vector.clone(),
    };
    Mode {
        re: p.re,
        im: p.im.abs(),
        frequency: p.frequency(),
        damping_ratio: p.damping_ratio(),
        shape,
        vector,
    }
}

/// The linear critical speed found by [`linear_critical_speed`].
#[derive(Debug, Clone)]
pub struct LinearCritical {
    /// \[m/s\] the speed where the real part of the mode that loses its damping crosses zero,
    /// interpolated linearly in the last bracket (that mode's eigenvalue at the bracket's lower
    /// end is the one nearest to it).
    pub critical_speed: f64,
    /// The least stable mode at the end of the bracket above the critical speed.
    pub mode: Mode,
    /// Every analysis made, in the order made: (speed, real part of the least damped
    /// oscillatory mode).
    pub scan: Vec<(f64, f64)>,
    /// The lowest speed analysed \[m/s\] at which a mode diverges ([`Mode::is_divergent`]), with
    /// its fastest-growing divergent mode there: an instability without oscillation, which the
    /// critical speed above does not count; `None` when no analysis found one.
    pub divergent: Option<(f64, Mode)>,
}

/// What a vehicle is linearised about.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Linearisation {
    /// Centred running on straight ideal track ([`modes_at`]).
    Straight,
    /// Steady curving through `case` ([`modes_in_curve`]); the analysis' speed replaces the
    /// case's.
    Curve {
        /// The curve (its speed is not used).
        case: CurveCase,
        /// The lengths of the case's run.
        run: CurvingRun,
        /// The quasi-static solution's limits.
        qs: QuasiStatic,
    },
}

impl Linearisation {
    /// The modes of `scene`'s vehicle at `speed` \[m/s\] about this state.
    pub fn modes(
        &self,
        scene: &Scene,
        speed: f64,
        opts: &ModalOptions,
    ) -> Result<ModalAnalysis, SimError> {
        match self {
            Linearisation::Straight => modes_at(scene, speed, opts),
            Linearisation::Curve { case, run, qs } => {
                let case = CurveCase { speed, ..*case };
                modes_in_curve(scene, &case, run, qs, opts)
            }
        }
    }
}

/// The lowest speed in `[lo, hi]` \[m/s\] at which an oscillatory mode of `scene`'s vehicle
/// becomes unstable in centred running on straight track: [`linear_critical_speed_about`] with
/// [`Linearisation::Straight`].
pub fn linear_critical_speed(
    scene: &Scene,
    opts: &ModalOptions,
    range: (f64, f64),
    n_scan: usize,
    rel_tol: f64,
    progress: &mut dyn FnMut(&ModalAnalysis),
) -> Result<LinearCritical, SimError> {
    linear_critical_speed_about(
        scene,
        &Linearisation::Straight,
        opts,
        range,
        n_scan,
        rel_tol,
        progress,
    )
}

/// The lowest speed in `[lo, hi]` \[m/s\] at which an oscillatory mode of `scene`'s vehicle,
/// linearised about `about`, becomes unstable: `n_scan` equal intervals are scanned from `lo`
/// for the first one over which the least damped mode's real part changes sign from negative
/// to positive, and that interval is bisected until it is narrower than `rel_tol` of its upper
/// end. Errors when the vehicle is already unstable at `lo` or stable up to `hi`. A mode that
/// diverges without oscillating ([`Mode::is_divergent`]) does not end the search; the lowest
/// speed analysed at which one does is reported beside the result
/// ([`LinearCritical::divergent`]) and in those errors.
pub fn linear_critical_speed_about(
    scene: &Scene,
    about: &Linearisation,
    opts: &ModalOptions,
    (lo, hi): (f64, f64),
    n_scan: usize,
    rel_tol: f64,
    progress: &mut dyn FnMut(&ModalAnalysis),
) -> Result<LinearCritical, SimError> {
    critical_speed_search(&scene.name, (lo, hi), n_scan, rel_tol, &mut |v| {
        let a = about.modes(scene, v, opts)?;
        progress(&a);
        Ok(a)
    })
}

/// The search of [`linear_critical_speed_about`] over the analyses that `analyse` makes at a
/// speed (a scene's name for the messages).
fn critical_speed_search(
    name: &str,
    (lo, hi): (f64, f64),
    n_scan: usize,
    rel_tol: f64,
    analyse: &mut dyn FnMut(f64) -> Result<ModalAnalysis, SimError>,
) -> Result<LinearCritical, SimError> {
    let mut divergent: Option<(f64, Mode)> = None;
    // what the search saw of divergent modes, for its result and its errors
    let divergence_text = |d: &Option<(f64, Mode)>| match d {
        Some((v, m)) => format!(
            "; note: a non-oscillatory mode diverges at {:.2} km/h (Re λ = {:+.4}/s, {})",
            v * 3.6,
            m.re,
            m.shape.first().map_or("", |s| s.0.as_str())
        ),
        None => String::new(),
    };
    let bad = |message: String, d: &Option<(f64, Mode)>| SimError::Study {
        message: format!(
            "linear critical speed of scene '{name}': {message}{}",
            divergence_text(d)
        ),
    };
    if !(lo > 0.0 && hi > lo && hi.is_finite() && rel_tol > 0.0 && n_scan >= 1) {
        return Err(bad(
            format!(
                "expected 0 < lo < hi (found {lo} and {hi} m/s), a positive tolerance ({rel_tol}) and at least one scan interval ({n_scan})"
            ),
            &None,
        ));
    }
    let mut scan = Vec::new();
    // each analysis: the least stable oscillatory mode's real part, and all oscillatory modes
    let mut eval = |v: f64,
                    scan: &mut Vec<(f64, f64)>,
                    divergent: &mut Option<(f64, Mode)>|
     -> Result<(f64, Vec<Mode>), SimError> {
        let a = analyse(v)?;
        if let Some(m) = a.divergent()
            && divergent.as_ref().is_none_or(|d| v < d.0)
        {
            *divergent = Some((v, m.clone()));
        }
        // the largest growth rate of the oscillatory modes, neutral ones counting 0 (stable)
        let g = a
            .modes
            .iter()
            .filter(|m| m.is_oscillatory())
            .map(Mode::growth)
            .reduce(f64::max)
            .ok_or_else(|| {
                bad(
                    format!("the vehicle has no oscillatory mode at {:.2} km/h", v * 3.6),
                    divergent,
                )
            })?;
        scan.push((v, g));
        Ok((
            g,
            a.modes.into_iter().filter(Mode::is_oscillatory).collect(),
        ))
    };
    let (mut a, (mut ga, mut modes_a)) = (lo, eval(lo, &mut scan, &mut divergent)?);
    if ga > 0.0 {
        return Err(bad(
            format!(
                "an oscillatory mode is already unstable at {:.2} km/h (Re λ = {ga:.4}/s): start lower",
                lo * 3.6
            ),
            &divergent,
        ));
    }
    let mut upper = None;
    for k in 1..=n_scan {
        let v = lo + (hi - lo) * k as f64 / n_scan as f64;
        let (g, modes) = eval(v, &mut scan, &mut divergent)?;
        if g > 0.0 {
            upper = Some((v, modes));
            break;
        }
        (a, ga, modes_a) = (v, g, modes);
    }
    let Some((mut b, mut modes_b)) = upper else {
        return Err(bad(
            format!(
                "every oscillatory mode is damped up to {:.2} km/h (the least damped: Re λ = {ga:.4}/s): search higher",
                hi * 3.6
            ),
            &divergent,
        ));
    };
    while b - a > rel_tol * b {
        let v = 0.5 * (a + b);
        let (g, modes) = eval(v, &mut scan, &mut divergent)?;
        if g <= 0.0 {
            (a, modes_a) = (v, modes);
        } else {
            (b, modes_b) = (v, modes);
        }
    }
    // The mode that is unstable at b, and the same mode at a (the nearest eigenvalue): its
    // real part crosses zero in between (the least stable mode at a may be another one).
    let mode = modes_b
        .iter()
        .max_by(|p, q| p.growth().total_cmp(&q.growth()))
        .expect("an unstable oscillatory mode at b")
        .clone();
    let (gb, ga) = (
        mode.re,
        modes_a
            .iter()
            .min_by(|p, q| {
                let d = |m: &Mode| (m.re - mode.re).hypot(m.im - mode.im);
                d(p).total_cmp(&d(q))
            })
            .map_or(f64::NEG_INFINITY, |m| m.re.min(0.0)),
    );
    let frac = if ga.is_finite() {
        (-ga) / (gb - ga).max(f64::MIN_POSITIVE)
    } else {
        1.0
    };
    Ok(LinearCritical {
        critical_speed: a + (b - a) * frac,
        mode,
        scan,
        divergent,
    })
}

/// Write to `path` an MCAP log of `mode` (of `analysis`, made of `scene` by [`modes_at`]) as
/// an animation: the states `x* + A Re(v e^{iωt})` over `periods` periods at 50 frames per
/// period, `x*` the equilibrium, `v` the mode's eigenvector scaled so that its largest position
/// component is `amplitude` (m, or rad with a lever of 1 m), ω its damped frequency (the growth
/// or decay left out, so that the shape repeats). The vehicle stays where it is on the track
/// (every frame's right-hand side at t = 0); the scene's log topics. Only oscillatory modes.
pub fn animate_mode(
    scene: &Scene,
    analysis: &ModalAnalysis,
    mode: &Mode,
    amplitude: f64,
    periods: f64,
    path: &std::path::Path,
) -> Result<LogStats, SimError> {
    let bad = |message: String| SimError::Study {
        message: format!("mode animation of scene '{}': {message}", scene.name),
    };
    if !mode.is_oscillatory() {
        return Err(bad(format!(
            "the mode is not oscillatory ({:.4} Hz, below {MIN_FREQUENCY} Hz)",
            mode.frequency
        )));
    }
    if !(amplitude.is_finite() && amplitude > 0.0 && amplitude <= 0.05) {
        return Err(bad(format!(
            "the amplitude must lie in (0, 50] mm, found {} mm",
            amplitude * 1e3
        )));
    }
    if !(periods.is_finite() && periods > 0.0 && periods <= 100.0) {
        return Err(bad(format!(
            "the number of periods must lie in (0, 100], found {periods}"
        )));
    }
    let mut study = modal_scene(scene, analysis.speed)?;
    study.name = format!(
        "{}: mode {:.3} Hz (damping ratio {:.4}) at {:.1} km/h, {} mm",
        scene.name,
        mode.frequency,
        mode.damping_ratio,
        analysis.speed * 3.6,
        amplitude * 1e3
    );
    let mut sim = Simulation::new(&study)?;
    let n = analysis.equilibrium.len();
    if mode.vector.len() != n || sim.model().dim() != n {
        return Err(bad(format!(
            "the mode has {} components, the model {} states",
            mode.vector.len(),
            sim.model().dim()
        )));
    }
    let w = mode.im;
    let frames_per_period = 50.0;
    let count = (periods * frames_per_period).ceil() as usize;
    let dt = 1.0 / (mode.frequency * frames_per_period);
    let mut frames = (0..=count).map(|k| {
        let t = k as f64 * dt;
        let (c, s) = ((w * t).cos(), (w * t).sin());
        let x = analysis
            .equilibrium
            .iter()
            .zip(&mode.vector)
            .map(|(x0, v)| x0 + amplitude * (v[0] * c - v[1] * s))
            .collect();
        (t, x)
    });
    sim.record_states(&study, path, 0.0, &mut frames)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mode(re: f64, frequency: f64, name: &str) -> Mode {
        let im = 2.0 * std::f64::consts::PI * frequency;
        Mode {
            re,
            im,
            frequency,
            damping_ratio: -re / re.hypot(im),
            shape: vec![(name.to_owned(), 1.0)],
            vector: Vec::new(),
        }
    }

    /// A spectrum at speed v \[m/s\]: a hunting mode losing its damping at 50 m/s and, from
    /// `diverges_from` on, a real mode growing at 0.01/s.
    fn spectrum(v: f64, diverges_from: f64) -> ModalAnalysis {
        let mut modes = vec![
            mode(0.2 * (v - 50.0), 3.0, "ws1.y"),
            mode(-30.0, 0.0, "ws1.x"),
        ];
        if v >= diverges_from {
            modes.push(mode(0.01, 0.0, "ws2.yaw"));
        }
        modes.sort_by(|p, q| q.re.total_cmp(&p.re));
        ModalAnalysis {
            speed: v,
            modes,
            states: 4,
            residual: (String::new(), 0.0),
            equilibrium: Vec::new(),
            balance: Ok(0),
            time: 0.0,
        }
    }

    #[test]
    fn a_divergent_mode_is_reported_beside_the_critical_speed_and_in_the_errors() {
        let run = |range: (f64, f64), diverges_from: f64| {
            critical_speed_search("t", range, 10, 1e-4, &mut |v| {
                Ok(spectrum(v, diverges_from))
            })
        };
        // hunting at 50 m/s; the real mode grows from 35 m/s: the scan sees it first at 36
        let r = run((10.0, 100.0), 35.0).unwrap();
        assert!(
            (r.critical_speed - 50.0).abs() < 0.01,
            "{}",
            r.critical_speed
        );
        let (v, m) = r.divergent.expect("the divergent mode");
        assert!(
            v == 37.0 && m.re == 0.01 && m.shape[0].0 == "ws2.yaw",
            "{v} {m:?}"
        );
        // none: none reported
        assert!(
            run((10.0, 100.0), f64::INFINITY)
                .unwrap()
                .divergent
                .is_none()
        );
        // found on a bisection only: the lowest speed analysed at which it grows
        let r = run((10.0, 100.0), 49.0).unwrap();
        assert!(
            r.divergent
                .as_ref()
                .is_some_and(|d| d.0 >= 49.0 && d.0 < 50.0),
            "{:?}",
            r.divergent
        );
        // a search that ends in an error says the vehicle diverges (first seen at 22 m/s)
        let e = run((10.0, 40.0), 20.0).unwrap_err().to_string();
        assert!(
            e.contains("search higher")
                && e.contains(
                    "a non-oscillatory mode diverges at 79.20 km/h (Re λ = +0.0100/s, ws2.yaw)"
                ),
            "{e}"
        );
        // a real mode within round-off of zero, or decaying, is not divergent
        assert!(!mode(0.5 * DIVERGENT_RATE, 0.0, "x").is_divergent());
        assert!(!mode(0.5, 1.0, "x").is_divergent());
        assert!(mode(2.0 * DIVERGENT_RATE, 0.0, "x").is_divergent());
    }
}
