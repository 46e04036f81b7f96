//! Running a scene: the initial state, the step loop, samples at the assessment's rate (every
//! few of them logged), blow-up checks, the MCAP log and the run summary.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

use railsim_contact::{Side, WheelsetPose, WheelsetVelocity};
use railsim_log::messages::{
    BodyState, BogieFrameMessage, CarbodyMessage, Creepages as LogCreepages, ElementMessage,
    FrameTransform, PatchMessage, Quaternion, Side as LogSide, WheelsetMessage, topics,
    wear_number,
};
use railsim_log::{Channel, LogHeader, LogStats, LogWriter, WriterOptions, step_time_ns};
use railsim_ode::{Integrator, Method, OdeSystem, Stats, StepOutcome, StopReason};
use railsim_track::SegmentKind;

use crate::assess::{
    Assessment, BogieSeries, ComfortSeries, CurveSection, Series, WheelSeries, assess,
};
use crate::dynamics::{
    CostSplit, Dynamics, ElementRecord, MemberKin, Workspace, frame_motion, rail_frame,
};
use crate::error::SimError;
use crate::math::{V3, add, cross, mul, mul_t, quaternion, rotation_rpy, scale, sub};
use crate::model::{MemberKind, MemberModel, SimModel};
use crate::scene::{InitialState, Scene, Topic};

/// \[m\] wheelset lateral displacement relative to the track beyond which a run stops as a
/// derailment (the flange has climbed the rail: flange-way clearance ≈ 8 mm, flange height
/// 28 mm).
pub const DERAILMENT_LATERAL: f64 = 0.040;
/// \[m\] wheelset lift above its nominal height beyond which a run stops as a derailment.
pub const DERAILMENT_LIFT: f64 = 0.025;
/// \[m\] displacement of a rail on an elastic support beyond which a run stops as unstable
/// (tens of times a static deflection).
pub const RAIL_DISPLACEMENT_LIMIT: f64 = 0.01;
/// \[m\] body displacement from its nominal position beyond which a run stops as unstable.
pub const BODY_DISPLACEMENT_LIMIT: f64 = 0.5;
/// \[rad\] body rotation beyond which a run stops as unstable.
pub const BODY_ROTATION_LIMIT: f64 = 0.3;
/// \[s\] first step size of the adaptive integrators when the scene gives none: the first
/// stages must stay near the contact equilibrium.
pub const FIRST_STEP: f64 = 1e-5;
/// \[s\] largest step of the adaptive integrators when the scene gives none: contact
/// stiffness and creep damping set the stability limit of explicit methods near 4 ms.
pub const DEFAULT_MAX_STEP: f64 = 2e-3;

/// A simulation of one scene: model, state, workspace and integrator.
pub struct Simulation {
    model: SimModel,
    ws: Option<Workspace>,
    integ: Integrator,
    /// The state the run starts from, at `t0`.
    x0: Vec<f64>,
    /// \[s\] the time the run starts at: 0, or where [`Simulation::start_from`] put it.
    t0: f64,
    t_end: f64,
    /// Wheel loads of the static solution, per wheelset \[left, right\].
    static_loads: Vec<[f64; 2]>,
    /// The quasi-static start's Newton iterations and largest scaled residual
    /// ([`InitialState::QuasiStatic`]); `None` for a static start.
    quasi_static: Option<(usize, f64)>,
}

/// One sampled instant: time, state and the outputs derived from it.
#[derive(Debug, Clone)]
pub struct Sample {
    /// \[s\]
    pub t: f64,
    /// \[ns\] log time of the sample (sample index × log period).
    pub t_ns: u64,
    /// The state vector.
    pub x: Vec<f64>,
    /// Per wheelset (numbered from the front): Y, Q per wheel, angle of attack, lateral
    /// displacement.
    pub wheelsets: Vec<WheelsetMessage>,
    /// \[m\] per wheelset: lateral displacement relative to the track centre line.
    pub lateral: Vec<f64>,
    /// \[m/s²\] per comfort point of the carbody (`RunSummary::assessment`'s `comfort`, same
    /// order): the specific force an accelerometer fixed there measures, longitudinal, lateral
    /// and vertical in the carbody's axes (at rest on level track: 0, 0 and +g).
    pub carbody: Vec<[f64; 3]>,
    /// \[m/s²\] per measuring point of the bogie frames (`RunSummary::assessment`'s `bogies`,
    /// the same order): the specific force in the frame's axes.
    pub bogie_frames: Vec<[f64; 3]>,
    /// Per force element (the vehicle's order): deflections, forces and state, local axes.
    pub elements: Vec<ElementRecord>,
    /// \[J\] per force element: the work it has absorbed since the run's first sample and the
    /// part of it dissipated (the trapezoidal rule on `ElementRecord::power` and
    /// `ElementRecord::dissipation` over the samples).
    pub element_work: Vec<[f64; 2]>,
}

/// What one force element absorbed over a run ([`RunSummary::elements`]).
#[derive(Debug, Clone)]
pub struct ElementEnergy {
    /// The element's name.
    pub name: String,
    /// Its type as written in the vehicle file.
    pub kind: &'static str,
    /// Whether its law dissipates (`ForceLaw::dissipates`); for the others the work is the
    /// change of the energy they store.
    pub dissipates: bool,
    /// \[J\] work absorbed from the bodies between the first and the last sample: the integral
    /// of `ElementRecord::power` by the trapezoidal rule over the samples (at the assessment's
    /// rate, `[assessment] rate_hz`, by default at or above 1 kHz, 2 kHz for the Hertz models).
    pub work: f64,
    /// \[J\] the part of `work` dissipated (the rest is the change of the energy it stores):
    /// the integral of `ElementRecord::dissipation`, likewise.
    pub dissipated: f64,
    /// \[W\] the dissipated energy over the time between the first and the last sample.
    pub mean_dissipation: f64,
    /// \[W\] the largest dissipation at a sample.
    pub peak_dissipation: f64,
}

/// What a finished run reports.
#[derive(Debug, Clone)]
pub struct RunSummary {
    /// \[s\] simulated time.
    pub t_end: f64,
    /// \[s\] wall-clock time of the step loop.
    pub wall: f64,
    /// The wheelsets' names in the vehicle file, by their numbers from the front (the numbers
    /// the other fields and the logs use).
    pub wheelset_names: Vec<String>,
    /// \[m\] per wheelset (numbered from the front): largest |lateral displacement|.
    pub max_lateral: Vec<f64>,
    /// \[-\] largest Y/Q of any wheel at a sample, with its wheelset and side (`None`
    /// without samples). EN 14363's (Y/Q)2m per wheel is in [`RunSummary::assessment`].
    pub max_y_over_q: Option<(f64, u32, Side)>,
    /// \[N\] largest Q of any wheel, with its wheelset and side.
    pub max_q: (f64, u32, Side),
    /// \[m\] on an elastic rail support: the largest lateral and vertical displacement (absolute
    /// values) of any rail at a sample, each with the wheelset and side of its wheel.
    pub max_rail: Option<[(f64, u32, Side); 2]>,
    /// The EN 14363 quantities against their limits: the track-shift force per axle ((ΣY)2m
    /// and the sliding r.m.s. stability criterion), per wheel (Y/Q)2m, Q and the quasi-static
    /// Y_qst and Q_qst in curves, the bogie frames' simplified stability criterion, and the
    /// carbody's ride quantities (Sperling's Wz, band-passed accelerations, N_MV) per comfort
    /// point (`crate::assess`).
    pub assessment: Assessment,
    /// Integrator statistics.
    pub stats: Stats,
    /// Samples logged (at the log rate; the assessment's between them are not counted).
    pub samples: u64,
    /// \[Hz\] the rate of the samples the assessment, the maxima "at a sample", the elements'
    /// energies and the digest come from (`[assessment] rate_hz`, by default the log rate's
    /// multiple at or above 1 kHz), a whole multiple of the log rate.
    pub assessment_rate_hz: f64,
    /// FNV-1a digest of the bits of every sampled state (at the assessment's rate, which
    /// includes the log's samples): equal digests mean identical runs.
    pub digest: u64,
    /// Cost of the right-hand side's stages.
    pub cost: CostSplit,
    /// Warm-started and cold contact searches (wheel evaluations) of the run; both zero when
    /// the scene turns the warm start off.
    pub contact_searches: (u64, u64),
    /// \[s\] time spent writing the log.
    pub logging: f64,
    /// The log, if one was written.
    pub log: Option<LogStats>,
    /// Per force element (the vehicle's order): the work it absorbed and the energy it dissipated
    /// over the run, the mean and largest dissipation.
    pub elements: Vec<ElementEnergy>,
}

impl RunSummary {
    /// Simulated time over wall-clock time.
    pub fn real_time_factor(&self) -> f64 {
        self.t_end / self.wall.max(1e-12)
    }
}

/// Options of a run that are not part of the scene.
#[derive(Debug, Clone, Default)]
pub struct RunOptions {
    /// Write the log here instead of the scene's path; `None` keeps the scene's.
    pub log_path: Option<PathBuf>,
    /// Write no log at all.
    pub no_log: bool,
    /// Stop at this time instead of the scene's end.
    pub t_end: Option<f64>,
    /// Measure the cost split (adds two clock reads per stage).
    pub timing: bool,
    /// Source texts to store in the log (name → text), so that a log describes itself.
    pub sources: BTreeMap<String, String>,
}

/// The offset basis of the 64-bit FNV-1a hash (Fowler, Noll and Vo; IETF draft-eastlake-fnv):
/// the start of [`fnv1a`].
pub const FNV1A_OFFSET: u64 = 0xcbf2_9ce4_8422_2325;

/// Feed `bytes` into the 64-bit FNV-1a hash `h` (prime 0x100000001b3), which starts at
/// [`FNV1A_OFFSET`]: the runs' state digest, and the digests of the data files a log lists.
pub fn fnv1a(h: &mut u64, bytes: &[u8]) {
    for &b in bytes {
        *h ^= u64::from(b);
        *h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
}

impl Simulation {
    /// Build the model and the initial state of `scene`: the static equilibrium of the vehicle
    /// on level track, each wheelset settled on its rails under its static load with the scene's
    /// initial disturbance, spin at free rolling (`settle_spins`), series dampers
    /// relaxed.
    pub fn new(scene: &Scene) -> Result<Simulation, SimError> {
        let mut model = SimModel::new(scene)?;
        let method = with_step_defaults(scene.integrator);
        let mut integ = Integrator::new(method, model.dim())?;
        // No step limit: the scene's duration bounds the run (a day at most) and a step that
        // collapses stops it (`StopReason::StepTooSmall`); the integrator's default of 10
        // million steps stopped an `rk4` run at 1 µs steps after 10 s.
        integ.set_max_steps(usize::MAX);
        let stat = scene
            .vehicle
            .static_equilibrium()
            .map_err(|e| SimError::Initial {
                message: e.to_string(),
            })?;
        // The vehicle file gives the nominal, loaded geometry: each element carries its static
        // force as a preload, and the bodies start at their nominal positions (plus the
        // wheelsets' mean sink on their rails, below).
        for (el, f) in model.elements.iter_mut().zip(&stat.element_force) {
            el.preload = *f;
        }
        let mut x0 = vec![0.0; model.dim()];
        let nb = scene.vehicle.bodies().len();
        let (_, v0, _) = model.motion(0.0);
        let mut ws = Workspace::new(&model);
        let mut dx = vec![0.0; model.dim()];
        // The spin each wheelset is settled at: first its nominal rolling, then its free rolling
        // found at the first pass's state, so that its heights, roll and rail deflections
        // balance the creep forces it starts with (the spin moves the creep forces' lateral and
        // vertical components: settled at the nominal spin and started at free rolling, the
        // Manchester vehicle's rails on `tracks/straight_elastic.toml` ran up to 0.21 µm off
        // their balance, beyond the 0.2 µm of test
        // `an_elastic_rail_support_starts_in_static_equilibrium`; settled at free rolling 0.11).
        let mut settle_spin: Vec<f64> = model
            .members
            .iter()
            .map(|mm| match mm.kind {
                MemberKind::Wheelset { radius, .. } => v0.max(1e-3) / radius,
                MemberKind::Body => 0.0,
            })
            .collect();
        for pass in 0..2 {
            x0.fill(0.0);
            let (sink, rolling) = place_wheelsets(
                &model,
                scene,
                &stat.wheel_loads,
                &settle_spin,
                pass == 0,
                &mut ws,
                &mut x0,
            )?;
            // (a frozen spin rolls at V / this radius; a free one's is replaced below)
            for (mm, r) in model.members.iter_mut().zip(&rolling) {
                if mm.is_wheelset() {
                    mm.rolling_radius = *r;
                }
            }
            follow_rails(&model, &mut x0);
            // Bodies follow the wheelsets' mean sink on their rails (the contact's deflection).
            let nw = scene.vehicle.wheelsets().len().max(1) as f64;
            for mm in model.members.iter().take(nb) {
                if let Some(ix) = mm.pos[2] {
                    x0[ix] += sink / nw;
                }
            }
            // Series dampers start relaxed; spins at free rolling.
            let mut d = Dynamics { model: &model, ws };
            d.rhs(0.0, &x0, &mut dx)
                .map_err(|e| SimError::Initial { message: e.0 })?;
            for (ei, el) in model.elements.iter().enumerate() {
                if let Some(ix) = el.internal {
                    let n = el.law.internal_states();
                    x0[ix..ix + n].copy_from_slice(&d.ws.series_delta[ei][..n]);
                }
            }
            settle_spins(&mut d, &mut x0, &mut dx, SpinTarget::FreeRolling)
                .map_err(|message| SimError::Initial { message })?;
            ws = d.ws;
            for (mm, spin) in model.members.iter().zip(settle_spin.iter_mut()) {
                if mm.is_wheelset() {
                    *spin = mm.rate[4].map_or(v0 / mm.rolling_radius, |ix| x0[ix]);
                }
            }
        }
        // A free spin's radius: the effective rolling radius V / Ω of its free rolling.
        for mm in model.members.iter_mut().filter(|m| m.is_wheelset()) {
            if let Some(ix) = mm.rate[4] {
                mm.rolling_radius = v0 / x0[ix];
            }
        }
        let mut sim = Simulation {
            model,
            ws: Some(ws),
            integ,
            x0,
            t0: 0.0,
            t_end: scene.duration(),
            static_loads: stat.wheel_loads,
            quasi_static: None,
        };
        if scene.initial_state == InitialState::QuasiStatic {
            // from the static equilibrium just built, which places every member on its frame
            let (mut x, iterations, residual) = crate::curving::quasi_static_start(&sim, scene)?;
            follow_rails(&sim.model, &mut x);
            sim.x0 = x;
            sim.quasi_static = Some((iterations, residual));
        }
        Ok(sim)
    }

    /// For a quasi-static start ([`InitialState::QuasiStatic`]): the Newton iterations it took
    /// (with those of a continuation) and the largest residual left, scaled to its limit (at
    /// most 1); `None` for a static start.
    pub fn quasi_static_start(&self) -> Option<(usize, f64)> {
        self.quasi_static
    }

    /// The model.
    pub fn model(&self) -> &SimModel {
        &self.model
    }

    /// The initial state.
    pub fn initial_state(&self) -> &[f64] {
        &self.x0
    }

    /// Start the next [`run`](Self::run) from state `x` at time `t0` \[s\] instead of the
    /// static equilibrium at 0 (a restart: e.g. a steady curving state with a disturbance added,
    /// `crate::modal::ModalAnalysis::time` and `equilibrium`). The run then goes from `t0` to the
    /// scene's end, samples on the log's grid from `t0` on, and the vehicle is where the speed
    /// profile puts it at `t0`. Errors on a state of the wrong length or with a non-finite value,
    /// or a `t0` outside `[0, end)`.
    pub fn start_from(&mut self, t0: f64, x: &[f64]) -> Result<(), SimError> {
        let bad = |message: String| SimError::Initial { message };
        if x.len() != self.x0.len() {
            return Err(bad(format!(
                "a restart state of {} values for a model of {} states",
                x.len(),
                self.x0.len()
            )));
        }
        if let Some(i) = x.iter().position(|v| !v.is_finite()) {
            return Err(bad(format!(
                "the restart state's '{}' is {}",
                self.model.state_names[i], x[i]
            )));
        }
        if !(t0.is_finite() && t0 >= 0.0 && t0 < self.t_end) {
            return Err(bad(format!(
                "a restart at t = {t0} s, outside the run's [0, {}) s",
                self.t_end
            )));
        }
        self.x0.copy_from_slice(x);
        self.t0 = t0;
        Ok(())
    }

    /// The sample (wheel forces, Y/Q, angles of attack, wear numbers, carbody readings) of
    /// state `x` at time `t`, as a run would record it there; for states found otherwise than
    /// by a run (a quasi-static solution).
    pub fn sample_at(&mut self, t: f64, x: &[f64]) -> Result<Sample, SimError> {
        let mut dynamics = Dynamics {
            model: &self.model,
            ws: self.ws.take().expect("workspace present"),
        };
        let mut state = LoopState::new(&self.model, 1.0, &self.static_loads);
        let mut dx = vec![0.0; x.len()];
        let t_ns = (t * 1e9).round() as u64;
        let r = record_sample(&mut dynamics, &mut state, t, t, t_ns, x, &mut dx);
        self.ws = Some(dynamics.ws);
        r.map(|()| state.sample)
    }

    /// Write to `path` a log of the states `frames` (log time, state), each recorded as a run
    /// records a sample (the scene's topics), with the right-hand side evaluated at time `t_rhs`
    /// for all of them (the vehicle stays where it is on the track); for states found otherwise
    /// than by a run (a mode's animation, `crate::modal::animate_mode`). The log carries no
    /// scene sources: it cannot be re-run.
    pub fn record_states(
        &mut self,
        scene: &Scene,
        path: &Path,
        t_rhs: f64,
        frames: &mut dyn Iterator<Item = (f64, Vec<f64>)>,
    ) -> Result<LogStats, SimError> {
        let mut rec =
            Recorder::create(path, scene, &self.model, &BTreeMap::new(), scene.duration())?;
        let mut dynamics = Dynamics {
            model: &self.model,
            ws: self.ws.take().expect("workspace present"),
        };
        let mut state = LoopState::new(&self.model, scene.log.rate_hz, &self.static_loads);
        let mut t_end = 0.0;
        let mut dx = vec![0.0; self.model.dim()];
        let result: Result<(), SimError> = (|| {
            for (t, x) in frames {
                let t_ns = (t * 1e9).round() as u64;
                record_sample(&mut dynamics, &mut state, t_rhs, t, t_ns, &x, &mut dx)?;
                rec.write(&self.model, &dynamics.ws, &state.sample)?;
                t_end = t;
            }
            Ok(())
        })();
        self.ws = Some(dynamics.ws);
        // the run's own error (a failed write, whose writer then refuses the closing too)
        // before the closing's
        let finished = rec.finish(state.digest, t_end, result.as_ref().err());
        result.and(finished)
    }

    /// \[N\] static wheel loads per wheelset (file order), `[left, right]`.
    pub fn static_loads(&self) -> &[[f64; 2]] {
        &self.static_loads
    }

    /// Run to the end (or `opts.t_end`), calling `progress(t, t_end)` after each accepted step
    /// and `on_sample` at every log sample (at the log rate). Writes the log when the scene asks
    /// for one and `opts.no_log` is unset.
    pub fn run(
        &mut self,
        scene: &Scene,
        opts: &RunOptions,
        progress: &mut dyn FnMut(f64, f64),
        on_sample: &mut dyn FnMut(&Sample),
    ) -> Result<RunSummary, SimError> {
        let t_end = opts.t_end.unwrap_or(self.t_end).min(self.t_end);
        if t_end <= self.t0 {
            return Err(SimError::Initial {
                message: format!(
                    "the run would end at {t_end} s, not after its start at {} s",
                    self.t0
                ),
            });
        }
        let log_path = opts
            .log_path
            .clone()
            .unwrap_or_else(|| scene.log.path.clone());
        let mut recorder = if opts.no_log || scene.log.topics.is_empty() {
            None
        } else {
            Some(Recorder::create(
                &log_path,
                scene,
                &self.model,
                &opts.sources,
                t_end,
            )?)
        };
        let mut dynamics = Dynamics {
            model: &self.model,
            ws: self.ws.take().expect("workspace present"),
        };
        dynamics.ws.timing = opts.timing;
        dynamics.ws.cost = CostSplit::default();
        dynamics.ws.failure = None;
        // Every run starts with cold contact searches (runs of one simulation do not depend on
        // each other); the counters are read as differences.
        let searches = |ws: &Workspace| {
            ws.warm_starts()
                .fold((0, 0), |(w, c), s| (w + s.warm_count, c + s.cold_count))
        };
        dynamics.ws.invalidate_warm_starts();
        let searches0 = searches(&dynamics.ws);
        let dt_ns = (1e9 / scene.log.rate_hz).round().max(1.0) as u64;
        // the assessment's samples: `per_log` of them per log sample, the log's among them
        // (`[assessment] rate_hz`, a whole multiple of the log rate; docs/models/dynamics.md,
        // "Aliasing")
        let per_log = scene.assessment_samples_per_log();
        let assessment_rate = scene.assessment_rate();
        let n = self.model.dim();
        let mut xs = vec![0.0; n];
        let mut dxs = vec![0.0; n];
        let mut state = LoopState::new(&self.model, assessment_rate, &self.static_loads);
        let wall = Instant::now();
        let mut logging = 0.0;
        // the first sample on the log's grid at or after the start
        let first = ((self.t0 * 1e9 - 0.5) / dt_ns as f64).ceil().max(0.0) as usize;
        // the next sample, counted on the assessment's grid
        let mut next = first * per_log;
        let mut logged = 0u64;
        let mut kinks_checked = self.t0;
        let mut kink_state = vec![0.0; n];
        let result: Result<(), SimError> = (|| {
            self.integ
                .set_breakpoints(&self.model.breakpoints(self.t0, t_end))?;
            self.integ.start(&dynamics, self.t0, &self.x0, t_end)?;
            loop {
                // Samples up to the integrator's time.
                loop {
                    let (log_ix, sub) = (next / per_log, next % per_log);
                    let t_ns =
                        step_time_ns(log_ix as u64, dt_ns)? + sub as u64 * dt_ns / per_log as u64;
                    let ts = t_ns as f64 * 1e-9;
                    // The integrator's time is a sum of steps: allow it to lag the sample time
                    // by rounding (1 ns) and evaluate the dense output at its own end then.
                    let t_int = self.integ.t();
                    if ts > t_int + 1e-9 || ts > t_end + 1e-9 {
                        break;
                    }
                    if next == first * per_log && ts <= self.t0 + 1e-9 {
                        xs.copy_from_slice(&self.x0);
                    } else {
                        self.integ.dense(ts.min(t_int), &mut xs)?;
                    }
                    record_sample(&mut dynamics, &mut state, ts, ts, t_ns, &xs, &mut dxs)?;
                    let sample = &state.sample;
                    check_limits(&self.model, sample, ts <= self.t0 + 1e-9)?;
                    if sub == 0 {
                        on_sample(sample);
                        if let Some(rec) = recorder.as_mut() {
                            let t0 = Instant::now();
                            rec.write(&self.model, &dynamics.ws, sample)?;
                            logging += t0.elapsed().as_secs_f64();
                        }
                        logged += 1;
                    }
                    next += 1;
                }
                if self.integ.is_finished() {
                    return Ok(());
                }
                // where a body's frame has crossed a kink of the track in the last step, its
                // rates jump so that its absolute velocity does not (the samples up to here
                // have been taken from the step's dense output)
                let t_int = self.integ.t();
                if t_int > kinks_checked {
                    let span = (kinks_checked, t_int);
                    if frame_kinks(&self.model, span, self.integ.x(), &mut kink_state) {
                        self.integ.jump(&kink_state)?;
                    }
                    kinks_checked = t_int;
                }
                match self.integ.step(&mut dynamics) {
                    StepOutcome::Accepted { t } => progress(t, t_end),
                    StepOutcome::Stop(StopReason::Reached) => {}
                    StepOutcome::Stop(reason) => {
                        let failure = dynamics.ws.failure.take();
                        return Err(stopped_integrator(
                            &self.model,
                            reason,
                            self.integ.t(),
                            failure,
                        ));
                    }
                }
            }
        })();
        let stats = self.integ.stats();
        let cost = dynamics.ws.cost;
        let searches1 = searches(&dynamics.ws);
        let contact_searches = (searches1.0 - searches0.0, searches1.1 - searches0.1);
        self.ws = Some(dynamics.ws);
        let log = match recorder {
            // A run that failed keeps its own error (a stop names time, body and quantity;
            // a failed write its cause, which the writer's refusal to close would replace).
            Some(rec) => match rec.finish(state.digest, self.integ.t(), result.as_ref().err()) {
                Ok(stats) => Some(stats),
                Err(_) if result.is_err() => None,
                Err(e) => return Err(e),
            },
            None => None,
        };
        let summarize = |log: Option<LogStats>, t_end: f64| {
            // static axle loads per wheelset from the front
            let mut axle_loads = vec![0.0; self.static_loads.len()];
            for (pair, q) in self.model.wheels.chunks(2).zip(&self.static_loads) {
                axle_loads[pair[0].wheelset_number as usize] = q[0] + q[1];
            }
            RunSummary {
                t_end,
                wall: wall.elapsed().as_secs_f64(),
                wheelset_names: self.model.wheelset_names(),
                max_lateral: state.max_lateral.clone(),
                max_y_over_q: state.max_yq,
                max_q: state.max_q,
                max_rail: state.max_rail,
                assessment: assess(&state.series, &axle_loads, &scene.assessment),
                stats,
                samples: logged,
                assessment_rate_hz: assessment_rate,
                digest: state.digest,
                cost,
                contact_searches,
                logging,
                log,
                elements: element_energy(&self.model, &state),
            }
        };
        if let Err(mut e) = result {
            if let SimError::Stopped {
                t,
                log: l,
                digest: d,
                summary,
                ..
            } = &mut e
            {
                *l = log.as_ref().map(|s| s.path.clone());
                *d = Some(state.digest);
                // the simulated time is that of the last good state, as the error reports it
                *summary = Some(Box::new(summarize(log, *t)));
            }
            return Err(e);
        }
        Ok(summarize(log, self.integ.t()))
    }
}

/// Per force element of `model`: the work absorbed and the energy dissipated over the samples of
/// `state`, the mean and largest dissipation.
fn element_energy(model: &SimModel, state: &LoopState) -> Vec<ElementEnergy> {
    let span = state.sampled.map_or(0.0, |[first, last]| last - first);
    model
        .elements
        .iter()
        .zip(&state.sample.element_work)
        .zip(&state.peak_dissipation)
        .map(|((el, &[work, dissipated]), &peak)| ElementEnergy {
            name: el.name.clone(),
            kind: el.law.type_name(),
            dissipates: el.law.dissipates(),
            work,
            dissipated,
            mean_dissipation: if span > 0.0 { dissipated / span } else { 0.0 },
            peak_dissipation: peak,
        })
        .collect()
}

/// A recording right-hand side of `x` at time `t_rhs` (the patch records and accelerometers
/// filled), folded into `state`'s sample at log time `t` (`t_ns`); a failing right-hand side
/// stops with the time `t`.
fn record_sample(
    dynamics: &mut Dynamics,
    state: &mut LoopState,
    t_rhs: f64,
    t: f64,
    t_ns: u64,
    x: &[f64],
    dx: &mut [f64],
) -> Result<(), SimError> {
    dynamics.ws.record = true;
    let r = dynamics.rhs(t_rhs, x, dx);
    dynamics.ws.record = false;
    r.map_err(|e| stopped_rhs(t, e.0, dynamics.ws.failure.take()))?;
    state.sample(dynamics.model, &dynamics.ws, t, t_ns, x);
    Ok(())
}

/// The scene's integrator with the defaults of contact-coupled runs: a small first step and a
/// step limit for the adaptive methods when the scene sets none.
fn with_step_defaults(mut m: Method) -> Method {
    if let Method::DormandPrince { h0, h_max, .. } | Method::AdaptiveExplicit { h0, h_max, .. } =
        &mut m
    {
        h0.get_or_insert(FIRST_STEP);
        if !h_max.is_finite() {
            *h_max = DEFAULT_MAX_STEP;
        }
    }
    m
}

/// The stop error of a failed right-hand side at `t`: the wheel and message of the failed
/// contact evaluation (`Workspace::failure`), else the integrator's message.
fn stopped_rhs(t: f64, msg: String, failure: Option<(String, String)>) -> SimError {
    let (body, quantity) = failure.unwrap_or_else(|| ("model".into(), msg));
    SimError::Stopped {
        t,
        body,
        quantity,
        log: None,
        digest: None,
        summary: None,
    }
}

fn stopped_integrator(
    model: &SimModel,
    reason: StopReason,
    t_now: f64,
    failure: Option<(String, String)>,
) -> SimError {
    let (t, body, quantity) = match reason {
        StopReason::RhsFailed { t, msg } => return stopped_rhs(t, msg, failure),
        StopReason::NonFinite { t, index } => (
            t,
            model
                .state_names
                .get(index)
                .cloned()
                .unwrap_or_else(|| format!("state {index}")),
            "became NaN or infinite".to_owned(),
        ),
        StopReason::StepTooSmall { t, h } => (
            t,
            "integrator".into(),
            format!("step size {h:.3e} s too small (the motion is too violent to follow)"),
        ),
        other => (t_now, "integrator".into(), format!("{other:?}")),
    };
    SimError::Stopped {
        t,
        body,
        quantity,
        log: None,
        digest: None,
        summary: None,
    }
}

/// What a limit crossed in the initial state says instead of "unstable" or "derailment": no
/// step has been taken, so the static state itself lies beyond the limit.
const INITIAL_BEYOND: &str = "in the initial state, before any step: the static equilibrium lies \
     beyond the limit (check gravity_m_per_s2, the masses, the suspension's stiffnesses and \
     the rail support)";

/// Stop on derailment or a runaway body; `initial`: the sample is the initial state.
fn check_limits(model: &SimModel, s: &Sample, initial: bool) -> Result<(), SimError> {
    let stop = |body: &str, quantity: String| SimError::Stopped {
        t: s.t,
        body: body.to_owned(),
        quantity,
        log: None,
        digest: None,
        summary: None,
    };
    let why = |running: &'static str| if initial { INITIAL_BEYOND } else { running };
    for (i, mm) in model.members.iter().enumerate() {
        let q = |k: usize| model.coord(i, k, &s.x);
        match mm.kind {
            MemberKind::Wheelset { .. } => {
                if q(1).abs() > DERAILMENT_LATERAL {
                    return Err(stop(
                        &mm.name,
                        format!(
                            "lateral displacement {:.1} mm exceeds {:.0} mm ({})",
                            q(1) * 1e3,
                            DERAILMENT_LATERAL * 1e3,
                            why("derailment")
                        ),
                    ));
                }
                if q(2) > DERAILMENT_LIFT {
                    return Err(stop(
                        &mm.name,
                        format!(
                            "lift {:.1} mm exceeds {:.0} mm ({})",
                            q(2) * 1e3,
                            DERAILMENT_LIFT * 1e3,
                            why("derailment")
                        ),
                    ));
                }
            }
            MemberKind::Body => {
                for k in 0..3 {
                    if q(k).abs() > BODY_DISPLACEMENT_LIMIT {
                        return Err(stop(
                            &mm.name,
                            format!(
                                "displacement {} = {:.3} m exceeds {BODY_DISPLACEMENT_LIMIT} m ({})",
                                ["x", "y", "z"][k],
                                q(k),
                                why("unstable")
                            ),
                        ));
                    }
                    if q(3 + k).abs() > BODY_ROTATION_LIMIT {
                        return Err(stop(
                            &mm.name,
                            format!(
                                "{} = {:.3} rad exceeds {BODY_ROTATION_LIMIT} rad ({})",
                                ["roll", "pitch", "yaw"][k],
                                q(3 + k),
                                why("unstable")
                            ),
                        ));
                    }
                }
            }
        }
    }
    for (wi, wheel) in model.wheels.iter().enumerate() {
        let r = model.rail_state(wi, &s.x);
        for (k, axis) in [(0, "lateral"), (1, "vertical")] {
            if r[k].abs() > RAIL_DISPLACEMENT_LIMIT {
                return Err(stop(
                    &format!(
                        "rail under wheelset '{}', {} wheel",
                        model.members[wheel.member.0].name,
                        wheel.side.name()
                    ),
                    format!(
                        "{axis} displacement {:.1} mm exceeds {:.0} mm ({})",
                        r[k] * 1e3,
                        RAIL_DISPLACEMENT_LIMIT * 1e3,
                        why("unstable")
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// A wheelset to settle on its rails.
#[derive(Clone, Copy)]
struct SettleJob {
    /// index of its left wheel in `SimModel::wheels`
    first_wheel: usize,
    /// \[m\] its track position
    s: f64,
    /// its pose: the lateral position and yaw are kept, height and roll found
    pose: WheelsetPose,
    /// \[m/s\] speed
    v: f64,
    /// \[rad/s\] spin
    spin: f64,
    /// \[m\] nominal rolling radius
    radius: f64,
    /// \[N\] static load of the wheelset, carried half by each wheel
    load: f64,
}

/// Settle a wheelset on its rails (each displaced by `support`) at the lateral position and yaw
/// of `job.pose`: find the height and roll at which each wheel carries half of `load`; also
/// returns the mean rolling radius (each wheel's the normal-force-weighted mean of its patches')
/// and each wheel's contact force. Each wheel's height comes from the
/// contact crate's load control; the roll is corrected by the difference of the two heights over
/// the wheel spacing until they agree to 1e-9 m (a fixed point: roll moves the contact points
/// on the profiles only to second order).
fn settle(
    model: &SimModel,
    job: &SettleJob,
    support: [[f64; 4]; 2],
    ws: &mut Workspace,
) -> Result<Settled, String> {
    let &SettleJob {
        first_wheel,
        s,
        pose,
        v,
        spin,
        radius,
        load,
    } = job;
    let vel = WheelsetVelocity {
        vx: v.max(1e-3),
        spin,
        ..Default::default()
    };
    let mut p = pose;
    let mut spacing = 1.5;
    for _ in 0..50 {
        let mut z = [0.0; 2];
        let mut y_contact = [0.0; 2];
        let mut r_roll = 0.0;
        let mut force = [[0.0; 3]; 2];
        for (k, wheel) in model.wheels[first_wheel..first_wheel + 2]
            .iter()
            .enumerate()
        {
            // Relative to this wheel's rail (moved by irregularities and `support`): find the rail-frame
            // height that carries the load, then the track-frame height that gives it.
            let (mut pr, mut vr) = (p, vel);
            // (the support's lead, a lever about the axle, does not enter the vertical balance)
            let (sup, _) =
                model.wheel_support(first_wheel + k, support[k], (s, radius, 0.0), &mut vr);
            let rail = rail_frame(model, wheel.side, s, vel.vx, radius, sup, &mut pr, &mut vr);
            let sol = wheel.contacts[model.track.rail_section_at(s)]
                .evaluate_with_load(wheel.side, &pr, &vr, 0.5 * load, 1e-10, &mut ws.contact)
                .map_err(|e| e.to_string())?;
            let (sd, cd) = rail.sin_cos();
            force[k] = rail.to_track(sol.force_track);
            z[k] = (sol.z + radius + sd * (p.y - rail.origin[0])) / cd + rail.origin[1] - radius;
            y_contact[k] = ws.contact.patches.first().map_or(0.0, |q| q.point_track[1]);
            // the wheel's rolling radius: its patches' radii weighted by their normal forces (a
            // Hertz zone split into wells gives several patches, the first not always the one
            // that carries the load)
            let (mut n_sum, mut nr_sum) = (0.0, 0.0);
            for q in &ws.contact.patches {
                n_sum += q.forces.fn_;
                nr_sum += q.forces.fn_ * q.rolling_radius;
            }
            r_roll += 0.5 * if n_sum > 0.0 { nr_sum / n_sum } else { radius };
        }
        if y_contact[0] > y_contact[1] {
            spacing = y_contact[0] - y_contact[1];
        }
        let dz = z[0] - z[1];
        p.z = 0.5 * (z[0] + z[1]);
        if dz.abs() < 1e-9 {
            return Ok(Settled {
                z: p.z,
                roll: p.roll,
                rolling_radius: r_roll,
                force,
                support,
            });
        }
        p.roll += dz / spacing;
    }
    Err(format!(
        "no equilibrium on the rails within 50 iterations (load {:.1} kN)",
        load * 1e-3
    ))
}

/// The rigid bodies' rate jumps at the kinks of the track (docs/models/dynamics.md, "Frame
/// kinematics"): where a body's frame, at `start + distance + p0` along the track (its own
/// millimetres of longitudinal motion left out, as in [`SimModel::breakpoints`], whose times end
/// the steps there), crosses the start of a segment in the time span `(t_a, t_b]`, the frame's
/// angular velocity V·D jumps with the Darboux vector D (the ends of a linear cant ramp, where
/// φ′ steps; a curve joined without a transition, where κ steps; the ends of a vertical
/// curve). The states are rates relative to the frame, so left alone the body's absolute angular
/// velocity and velocity would jump with it, an impulse no force gives: its free relative rates
/// are lowered by the jump Δ (frame components) and its free translational rates by Δ × r, r its
/// centre of gravity from the frame's origin, so that its motion is continuous and its suspension
/// makes it follow. Wheelsets keep their rates: the stiff contact makes them follow the rails'
/// kink at once (an ideal kink of rigid rails would give a short, unrealistically large contact
/// impulse; a real one is rounded). Where a body crosses one, the state `x` with the jumps is
/// written to `out` and `true` returned; elsewhere `out` is left alone (no copy in the step loop).
fn frame_kinks(model: &SimModel, (t_a, t_b): (f64, f64), x: &[f64], out: &mut [f64]) -> bool {
    let (d_a, _, _) = model.motion(t_a);
    let (d_b, v, vdot) = model.motion(t_b);
    let mut changed = false;
    for (i, mm) in model.members.iter().enumerate() {
        if mm.is_wheelset() {
            continue;
        }
        let (s_a, s_b) = (model.start + d_a + mm.p0[0], model.start + d_b + mm.p0[0]);
        for seg in model.track.segments().iter().skip(1) {
            let sj = seg.s_start;
            if !(sj > s_a + 1e-9 && sj <= s_b + 1e-9) {
                continue;
            }
            let at = |s: f64| frame_motion(&model.track.frame_at(s), v, vdot);
            let (before, after) = (at(sj - 1e-7), at(sj + 1e-7));
            // the jump in the frame's components (the frame itself is continuous there)
            let jump = mul_t(&after.frame, sub(after.omega, before.omega));
            if jump.iter().all(|j| j.abs() < 1e-12) {
                continue;
            }
            let r = [
                0.0,
                mm.p0[1] + model.coord(i, 1, x),
                mm.p0[2] + model.coord(i, 2, x),
            ];
            let dv = cross(jump, r);
            if !changed {
                out.copy_from_slice(x);
                changed = true;
            }
            for k in 0..3 {
                for (slot, delta) in [(mm.rate[k], dv[k]), (mm.rate[k + 3], jump[k])] {
                    if let Some(ix) = slot {
                        out[ix] -= delta;
                    }
                }
            }
        }
    }
    changed
}

/// Set each wheelset's lateral, vertical and roll rates to those of its rails at its position at
/// t = 0, moving under it with the irregularities at the speed V: V·d(alignment)/ds,
/// V·d(level)/ds and V·d(cross level)/ds over the cant base (the rail frame's motion of
/// `dynamics::rail_frame`). A wheelset settled at rest on rails that move under it would start
/// with their vertical velocity as a penetration rate against the stiff contact: the Manchester
/// vehicle started from the quasi-static state in the irregular R = 1200 m curve at 160 km/h had
/// wheel loads between 1.7 and 131 kN in its first 0.05 s (38.5–70.0 kN with these rates), and
/// from the static state at s = 300 m on the irregular tangent 2.7–90.2 kN (47.8–59.5 kN; test
/// `the_wheelsets_start_with_the_rails_moving_under_them`). No change on smooth rails.
fn follow_rails(model: &SimModel, x: &mut [f64]) {
    let Some(irr) = model.track.irregularities() else {
        return;
    };
    let (_, v0, _) = model.motion(0.0);
    for mm in model.members.iter().filter(|m| m.is_wheelset()) {
        let ir = irr.at(model.start + mm.p0[0]);
        let rates = [
            v0 * ir.dlateral_ds,
            v0 * ir.dvertical_ds,
            v0 * ir.dcross_level_ds / model.cant_base,
        ];
        for (k, rate) in [1, 2, 3].into_iter().zip(rates) {
            if let Some(ix) = mm.rate[k] {
                x[ix] = rate;
            }
        }
    }
}

/// One pass of [`Simulation::new`]'s placement of the wheelsets: each settled on its rails
/// under its static load (`wheel_loads`, file order) with the scene's initial disturbance, at
/// spin `spins[member]`; writes its lateral position, height, roll, yaw, its rails' deflections
/// and a first spin (`V / r` on the first pass, `spins` after: the first guess of
/// [`settle_spins`]) into `x0`. Returns the wheelsets' summed sink on their rails and each
/// member's rolling radius (0 for bodies).
fn place_wheelsets(
    model: &SimModel,
    scene: &Scene,
    wheel_loads: &[[f64; 2]],
    spins: &[f64],
    first_pass: bool,
    ws: &mut Workspace,
    x0: &mut [f64],
) -> Result<(f64, Vec<f64>), SimError> {
    let nb = scene.vehicle.bodies().len();
    let (_, v0, _) = model.motion(0.0);
    let mut sink = 0.0;
    let mut rolling = vec![0.0; model.members.len()];
    for (wi, mm) in model.members.iter().enumerate().skip(nb) {
        let MemberKind::Wheelset {
            first_wheel,
            radius,
        } = mm.kind
        else {
            continue;
        };
        let w = wi - nb;
        let load = wheel_loads[w][0] + wheel_loads[w][1];
        let (mut y, mut yaw) = (0.0, 0.0);
        if w == scene.initial.wheelset.index() {
            y = scene.initial.lateral_offset;
            yaw = scene.initial.yaw;
        }
        let pose = WheelsetPose {
            y: mm.p0[1] + y,
            z: mm.p0[2] - radius,
            roll: 0.0,
            yaw,
        };
        let s_w = model.start + mm.p0[0];
        let Settled {
            z,
            roll,
            rolling_radius: r_roll,
            support,
            ..
        } = settle_on_rails(
            model,
            &SettleJob {
                first_wheel,
                s: s_w,
                pose,
                v: v0,
                spin: spins[wi],
                radius,
                load,
            },
            ws,
        )
        .map_err(|message| SimError::Initial {
            message: format!("wheelset '{}': {message}", mm.name),
        })?;
        for (k, wheel) in model.wheels[first_wheel..first_wheel + 2]
            .iter()
            .enumerate()
        {
            if let Some(i) = wheel.rail {
                x0[i] = support[k][0];
                x0[i + 1] = support[k][1];
            }
        }
        sink += z - (mm.p0[2] - radius);
        let set = |x: &mut [f64], k: usize, val: f64| {
            if let Some(ix) = mm.pos[k] {
                x[ix] = val;
            }
        };
        set(x0, 1, y);
        set(x0, 2, z + radius - mm.p0[2]);
        set(x0, 3, roll);
        set(x0, 5, yaw);
        // (the first guess of `settle_spins`)
        if let Some(ix) = mm.rate[4] {
            x0[ix] = if first_pass { v0 / r_roll } else { spins[wi] };
        }
        rolling[wi] = r_roll;
    }
    Ok((sink, rolling))
}

/// Newton iterations of [`settle_spins`] at most.
const SPIN_ITERATIONS: usize = 20;
/// \[rad/s²\] spin acceleration left by [`settle_spins`] against its target (1e-4 N·m on an
/// axle of I_y = 112 kg·m², against ±4 kN·m of creep torque per wheel at a creepage of 1e-3).
const SPIN_TOLERANCE: f64 = 1e-6;

/// What [`settle_spins`] sets each free wheelset spin to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum SpinTarget {
    /// **Free rolling**: the wheels' creep forces exert no torque about the axle, and the spin
    /// accelerates at T/I_y under the wheelset's traction or brake torque T alone (zero
    /// without one). The start of a run ([`Simulation::new`]).
    FreeRolling,
    /// **Rolling equilibrium**: no spin acceleration; the creep torque balances T (free rolling
    /// when T = 0). The linearisation point of a modal analysis (`modal::modes_at`).
    Equilibrium,
}

/// Set each free wheelset spin rate Ω of state `x` so that its spin acceleration, as the
/// right-hand side at t = 0 computes it, is `target`'s: T/I_y for free rolling (no creep torque
/// Σ (r_c × F_c + M_c)·e_y over its contact patches), 0 for the rolling equilibrium. V / r with
/// r a rolling radius from the patches is only the first guess: the contact model's
/// longitudinal creepage is taken where its solution takes it and its creep force integrates
/// the creepage's variation over the patch, so that V / r left the default Manchester
/// vehicle's axles accelerating at t = 0: `polach` and `fastsim` 76 rad/s² (the first of two
/// wells, 4.7 kN at r = 460.364 mm, gave the spin; the other, 49.9 kN at 459.906 mm, then rolled
/// at ξ = +9.9e-4 with Fx = −9.2 kN per wheel), `stripes` −14.3 rad/s² (ξ = 0 at the reference
/// point, but the conformal patch's Fx = +1.7 kN per wheel).
///
/// Newton's method on each spin's own acceleration (Dennis & Schnabel, *Numerical Methods for
/// Unconstrained Optimization and Nonlinear Equations*, 1983, ch. 2, the one-variable case),
/// its derivative by a forward difference of 1e-7 max(|Ω|, 1 rad/s). The axles are independent
/// (a wheelset's spin acceleration depends on its own spin only, through its contact forces: the
/// accelerations are explicit per member, `dynamics`), so one right-hand side serves all of
/// them: one evaluation per iteration for the derivative instead of the 2 per axle of a central
/// difference, and Newton's solution is defined by the residual test, not by the derivative's
/// accuracy. The step is limited to 1 % of Ω (a creepage of 0.01, beyond saturation; the whole
/// step where every patch slides and the derivative vanishes), so that a derivative taken
/// across a kink of piecewise-smooth forces (STRIPES' strips) cannot throw the spin far away; to
/// [`SPIN_TOLERANCE`] within [`SPIN_ITERATIONS`], or an error naming the wheelset and what is
/// left, as is a spin acceleration that grows with the spin (no rolling equilibrium).
///
/// (This one function replaces two near-copies: the run's start, which had these numerics, and
/// the modal analysis' settling, which took a central difference per axle with no step limit
/// and stopped silently after 20 iterations, so that a linearisation about an unsettled spin
/// would have gone unnoticed.) Leaves the right-hand side at `x` in `dx`; the error is the
/// message, which the caller places in its context.
pub(crate) fn settle_spins(
    d: &mut Dynamics,
    x: &mut [f64],
    dx: &mut [f64],
    target: SpinTarget,
) -> Result<(), String> {
    let model = d.model;
    // each free spin's state index and its target acceleration
    let spins: Vec<(usize, f64, &str)> = model
        .members
        .iter()
        .filter(|m| m.is_wheelset())
        .filter_map(|m| {
            let goal = match target {
                SpinTarget::FreeRolling => m.torque / m.inertia[1][1],
                SpinTarget::Equilibrium => 0.0,
            };
            m.rate[4].map(|i| (i, goal, m.name.as_str()))
        })
        .collect();
    let rhs = |d: &mut Dynamics, x: &[f64], dx: &mut [f64]| d.rhs(0.0, x, dx).map_err(|e| e.0);
    let what = match target {
        SpinTarget::FreeRolling => "free rolling",
        SpinTarget::Equilibrium => "rolling equilibrium",
    };
    let mut dh = vec![0.0; x.len()];
    let (mut base, mut steps) = (vec![0.0; spins.len()], vec![0.0; spins.len()]);
    rhs(d, x, dx)?;
    for iteration in 0..=SPIN_ITERATIONS {
        // the spin furthest from its target
        let worst = spins
            .iter()
            .map(|&(i, goal, name)| (dx[i] - goal, name))
            .max_by(|a, b| a.0.abs().total_cmp(&b.0.abs()));
        let Some((left, name)) = worst else {
            return Ok(());
        };
        if left.abs() < SPIN_TOLERANCE {
            return Ok(());
        }
        if iteration == SPIN_ITERATIONS {
            return Err(format!(
                "wheelset '{name}': no {what} within {SPIN_ITERATIONS} iterations (spin acceleration {left:.3e} rad/s² left)"
            ));
        }
        for (k, &(i, ..)) in spins.iter().enumerate() {
            base[k] = x[i];
            x[i] += 1e-7 * base[k].abs().max(1.0);
        }
        rhs(d, x, &mut dh)?;
        for (k, &(i, goal, name)) in spins.iter().enumerate() {
            let h = x[i] - base[k];
            x[i] = base[k];
            let slope = (dh[i] - dx[i]) / h;
            // (more spin, the wheels faster over the rails: a braking creep torque; none where
            // every patch slides)
            if slope.is_nan() || slope > 0.0 {
                return Err(format!(
                    "wheelset '{name}': no {what}: the spin acceleration grows with the spin ({slope:.3e} 1/s)"
                ));
            }
            let (left, limit) = (dx[i] - goal, 0.01 * x[i].abs());
            steps[k] = if slope < 0.0 {
                (-left / slope).clamp(-limit, limit)
            } else {
                limit.copysign(left)
            };
        }
        for (&(i, ..), step) in spins.iter().zip(&steps) {
            x[i] += step;
        }
        rhs(d, x, dx)?;
    }
    Ok(())
}

/// A wheelset settled on its rails by [`settle`] or [`settle_on_rails`].
struct Settled {
    /// \[m\] height of the wheelset (track frame)
    z: f64,
    /// \[rad\] roll
    roll: f64,
    /// \[m\] mean rolling radius of its two wheels, each the normal-force-weighted mean of its
    /// patches' (the first guess of [`settle_spins`]; a frozen spin's radius)
    rolling_radius: f64,
    /// \[N\] each wheel's contact force (wheelset's track frame) at its settled height
    force: [[f64; 3]; 2],
    /// each rail's (y, z, vy, vz) \[m, m/s\]: the static deflection, zero on rigid rails
    support: [[f64; 4]; 2],
}

/// [`settle`] a wheelset on rails that may sink: on an elastic rail support each rail lies at
/// the static deflection d = −F/k under its wheel's contact force F, itself a function of the
/// deflections. Newton's method on the four deflections (each rail's y and z), the Jacobian of
/// F by forward differences of 0.1 µm, until they change by less than 1 nm.
///
/// (The plain fixed point d ← −F(d)/k converges only where F changes with a rail's position
/// more slowly than its support's stiffness: at 1 MN/m laterally `stripes` with the wheelset
/// 1 mm off centre diverged.)
fn settle_on_rails(
    model: &SimModel,
    job: &SettleJob,
    ws: &mut Workspace,
) -> Result<Settled, String> {
    use faer::linalg::solvers::Solve;
    let settled = settle(model, job, [[0.0; 4]; 2], ws)?;
    let Some(sup) = model.rail_support else {
        return Ok(settled);
    };
    let k = [sup.lateral_stiffness, sup.vertical_stiffness];
    // the deflections x (left y, z, right y, z; from zero) and the residual x + F(x)/k at them
    let unpack = |x: &[f64; 4]| [[x[0], x[1], 0.0, 0.0], [x[2], x[3], 0.0, 0.0]];
    let residual = |x: &[f64; 4], s: &Settled| {
        let mut r = [0.0; 4];
        for side in 0..2 {
            for c in 0..2 {
                r[2 * side + c] = x[2 * side + c] + s.force[side][c + 1] / k[c];
            }
        }
        r
    };
    let mut x = [0.0; 4];
    let mut current = settled;
    const H: f64 = 1e-7;
    for _ in 0..20 {
        let r = residual(&x, &current);
        let mut jac = faer::Mat::<f64>::zeros(4, 4);
        for col in 0..4 {
            let mut xh = x;
            xh[col] += H;
            let sh = settle(model, job, unpack(&xh), ws)?;
            let rh = residual(&xh, &sh);
            for row in 0..4 {
                jac[(row, col)] = (rh[row] - r[row]) / H;
            }
        }
        let mut b = faer::Mat::<f64>::zeros(4, 1);
        for row in 0..4 {
            b[(row, 0)] = -r[row];
        }
        let dx = jac.partial_piv_lu().solve(&b);
        let mut change = 0.0f64;
        for row in 0..4 {
            let d = dx[(row, 0)];
            if !d.is_finite() {
                return Err("the rails' static deflection has a singular Jacobian".into());
            }
            x[row] += d;
            change = change.max(d.abs());
        }
        let support = unpack(&x);
        current = settle(model, job, support, ws)?;
        if change < 1e-9 {
            return Ok(Settled { support, ..current });
        }
    }
    Err("the rails' static deflection did not settle within 20 Newton iterations".into())
}

/// Maxima and digest carried through the loop.
struct LoopState {
    max_lateral: Vec<f64>,
    max_yq: Option<(f64, u32, Side)>,
    max_q: (f64, u32, Side),
    max_rail: Option<[(f64, u32, Side); 2]>,
    /// What the assessment is made from, a few values per sample: distance, track-shift force
    /// per wheelset, wheel forces, wheelset positions, carbody and bogie-frame accelerations.
    series: Series,
    digest: u64,
    /// The current sample, updated in place.
    sample: Sample,
    /// \[s\] times of the first and the last sample so far
    sampled: Option<[f64; 2]>,
    /// \[W\] per force element: the largest dissipation at a sample
    peak_dissipation: Vec<f64>,
}

impl LoopState {
    /// The state of a run of `model` sampled at `rate_hz`, with the static wheel loads
    /// `static_loads` (per wheelset in the model's order, \[left, right\]).
    fn new(model: &SimModel, rate_hz: f64, static_loads: &[[f64; 2]]) -> LoopState {
        let n_ws = model.wheels.len() / 2;
        let wheels = model
            .wheels
            .iter()
            .enumerate()
            .map(|(i, w)| WheelSeries {
                wheelset: w.wheelset_number,
                side: w.side,
                static_load: static_loads.get(i / 2).map_or(0.0, |q| q[i % 2]),
                y: Vec::new(),
                q: Vec::new(),
            })
            .collect();
        let curves = model
            .track
            .segments()
            .iter()
            .filter(|g| g.kind == SegmentKind::Curve && g.curvature_start != 0.0)
            .map(|g| CurveSection {
                s: [g.s_start, g.s_start + g.length],
                radius: 1.0 / g.curvature_start,
                cant: g.cant_start,
            })
            .collect();
        let bogies = model
            .bogies
            .iter()
            .map(|b| BogieSeries {
                name: model.members[b.member].name.clone(),
                mass: b.mass,
                points: b
                    .points
                    .iter()
                    .map(|(name, _)| (name.clone(), Vec::new()))
                    .collect(),
            })
            .collect();
        let mut state = LoopState {
            max_lateral: vec![0.0; n_ws],
            max_yq: None,
            max_q: (0.0, 0, Side::Left),
            max_rail: model
                .rail_support
                .map(|_| [(0.0, 0, Side::Left), (0.0, 0, Side::Left)]),
            series: Series {
                rate_hz,
                distance: Vec::new(),
                sum_y: vec![Vec::new(); n_ws],
                comfort: Vec::new(),
                wheels,
                wheelset_position: vec![Vec::new(); n_ws],
                curves,
                bogies,
            },
            digest: FNV1A_OFFSET,
            sample: Sample {
                t: 0.0,
                t_ns: 0,
                x: vec![0.0; model.dim()],
                wheelsets: (0..model.wheels.len() / 2)
                    .map(|n| WheelsetMessage {
                        t_s: 0.0,
                        wheelset: n as u32,
                        y_left_n: 0.0,
                        q_left_n: 0.0,
                        y_right_n: 0.0,
                        q_right_n: 0.0,
                        y_over_q_left: 0.0,
                        y_over_q_right: 0.0,
                        angle_of_attack_rad: 0.0,
                        wear_number_left_n: 0.0,
                        wear_number_right_n: 0.0,
                        rail_displacement_m: None,
                    })
                    .collect(),
                lateral: vec![0.0; model.wheels.len() / 2],
                carbody: Vec::new(),
                bogie_frames: vec![[0.0; 3]; model.bogies.iter().map(|b| b.points.len()).sum()],
                elements: vec![ElementRecord::default(); model.elements.len()],
                element_work: vec![[0.0; 2]; model.elements.len()],
            },
            sampled: None,
            peak_dissipation: vec![0.0; model.elements.len()],
        };
        if let Some((_, points)) = &model.comfort {
            state.series.comfort = points
                .iter()
                .map(|p| ComfortSeries {
                    name: p.name.clone(),
                    ..Default::default()
                })
                .collect();
            state.sample.carbody = vec![[0.0; 3]; points.len()];
        }
        state
    }

    /// Update the sample in place from the state `x` and the recording evaluation `ws` at `t`
    /// (nothing allocated but for the growth of the series the assessment is made from: a few
    /// values per sample), fold it into the maxima and digest.
    fn sample(&mut self, model: &SimModel, ws: &Workspace, t: f64, t_ns: u64, x: &[f64]) {
        for &xi in x {
            fnv1a(&mut self.digest, &xi.to_bits().to_le_bytes());
        }
        let dist = ws.track_position - model.start;
        let smp = &mut self.sample;
        smp.t = t;
        smp.t_ns = t_ns;
        smp.x.copy_from_slice(x);
        // the work absorbed since the last sample, by the trapezoidal rule
        let dt = self.sampled.map_or(0.0, |[_, last]| t - last);
        for (((w, old), new), peak) in smp
            .element_work
            .iter_mut()
            .zip(&smp.elements)
            .zip(&ws.elements)
            .zip(&mut self.peak_dissipation)
        {
            w[0] += 0.5 * dt * (old.power + new.power);
            w[1] += 0.5 * dt * (old.dissipation + new.dissipation);
            *peak = peak.max(new.dissipation);
        }
        self.sampled = Some([self.sampled.map_or(t, |[first, _]| first), t]);
        smp.elements.copy_from_slice(&ws.elements);
        self.series.distance.push(dist);
        if let Some((cb, points)) = &model.comfort {
            let k = &ws.kin[*cb];
            let carbody_x = model.track_x(*cb, ws.track_position, x);
            for ((c, d), out) in self
                .series
                .comfort
                .iter_mut()
                .zip(points)
                .zip(&mut smp.carbody)
            {
                let f_body = specific_force(k, d.offset, model.gravity);
                c.longitudinal.push(f_body[0]);
                c.lateral.push(f_body[1]);
                c.vertical.push(f_body[2]);
                c.position.push(carbody_x + d.offset[0]);
                *out = f_body;
            }
        }
        let mut out = smp.bogie_frames.iter_mut();
        for (b, series) in model.bogies.iter().zip(&mut self.series.bogies) {
            let k = &ws.kin[b.member];
            for ((_, offset), (_, values)) in b.points.iter().zip(&mut series.points) {
                let f = specific_force(k, *offset, model.gravity);
                values.push(f[1]);
                if let Some(o) = out.next() {
                    *o = f;
                }
            }
        }
        for (i, pair) in model.wheels.chunks(2).enumerate() {
            let number = pair[0].wheelset_number;
            let m = pair[0].member.0;
            let fl = ws.wheel_force[2 * i];
            let fr = ws.wheel_force[2 * i + 1];
            // Y on the rail toward its field side; Q on the rail downward.
            let (yl, ql, yr, qr) = (-fl[1], fl[2], fr[1], fr[2]);
            let yq = |y: f64, q: f64| if q > 0.0 { y / q } else { 0.0 };
            let wear = |wheel: usize| -> f64 {
                ws.patches
                    .iter()
                    .filter(|p| p.wheel == wheel)
                    .map(|p| p.weight * patch_wear(&p.result))
                    .sum()
            };
            let msg = WheelsetMessage {
                t_s: t,
                wheelset: number,
                y_left_n: yl,
                q_left_n: ql,
                y_right_n: yr,
                q_right_n: qr,
                y_over_q_left: yq(yl, ql),
                y_over_q_right: yq(yr, qr),
                angle_of_attack_rad: model.coord(m, 5, x),
                wear_number_left_n: wear(2 * i),
                wear_number_right_n: wear(2 * i + 1),
                rail_displacement_m: model.rail_support.map(|_| {
                    let (l, r) = (model.rail_state(2 * i, x), model.rail_state(2 * i + 1, x));
                    [l[0], l[1], r[0], r[1]]
                }),
            };
            // the track-shift force: the two wheels' lateral forces on the rails, toward +y
            self.series.sum_y[number as usize].push(yl - yr);
            for (k, (y, q)) in [(yl, ql), (yr, qr)].into_iter().enumerate() {
                let w = &mut self.series.wheels[2 * i + k];
                w.y.push(y);
                w.q.push(q);
            }
            self.series.wheelset_position[number as usize].push(model.track_x(
                m,
                ws.track_position,
                x,
            ));
            let y = model.wheelset_pose(m, x).y;
            smp.lateral[number as usize] = y;
            let ml = &mut self.max_lateral[number as usize];
            *ml = ml.max(y.abs());
            for (k, (side, yqv, q)) in [
                (Side::Left, msg.y_over_q_left, ql),
                (Side::Right, msg.y_over_q_right, qr),
            ]
            .into_iter()
            .enumerate()
            {
                if self.max_yq.is_none_or(|m| yqv > m.0) {
                    self.max_yq = Some((yqv, number, side));
                }
                if q > self.max_q.0 {
                    self.max_q = (q, number, side);
                }
                if let (Some(max), Some(d)) = (&mut self.max_rail, msg.rail_displacement_m) {
                    for (j, m) in max.iter_mut().enumerate() {
                        let v = d[2 * k + j].abs();
                        if v > m.0 {
                            *m = (v, number, side);
                        }
                    }
                }
            }
            smp.wheelsets[number as usize] = msg;
        }
    }
}

/// \[m/s²\] what an accelerometer fixed to a member at `offset` (member axes, from its centre
/// of gravity) measures, in the member's axes: the specific force at the centre of gravity (its
/// acceleration minus gravity; for free coordinates the forces other than gravity over the
/// mass) plus the rigid-body terms of the offset, α × r + ω × (ω × r).
fn specific_force(k: &MemberKin, offset: [f64; 3], gravity: f64) -> [f64; 3] {
    let f_cog = add(k.accel, [0.0, 0.0, gravity]);
    let arm = mul(&k.orient, offset);
    let f = add(
        f_cog,
        add(cross(k.alpha, arm), cross(k.omega, cross(k.omega, arm))),
    );
    mul_t(&k.orient, f)
}

/// A patch's creepages as the log writes them.
fn log_creepages(r: &railsim_contact::PatchResult) -> LogCreepages {
    LogCreepages {
        xi: r.creepages.xi,
        eta: r.creepages.eta,
        phi_per_m: r.creepages.phi,
    }
}

/// \[N\] a patch's wear number Tγ (`railsim_log::wear_number`).
fn patch_wear(r: &railsim_contact::PatchResult) -> f64 {
    wear_number(r.forces.fx, r.forces.fs, &log_creepages(r))
}

/// The MCAP log of a run: the channels of the topics chosen in the scene (empty or `None` for
/// the others).
struct Recorder {
    writer: LogWriter,
    bodies: Vec<Channel<BodyState>>,
    contact: Vec<Channel<PatchMessage>>,
    wheelsets: Vec<Channel<WheelsetMessage>>,
    /// Per comfort point of the carbody, with its name.
    carbody: Vec<(Channel<CarbodyMessage>, String)>,
    /// Per measuring point of the bogie frames, with its name.
    bogie_frames: Vec<(Channel<BogieFrameMessage>, String)>,
    /// Per force element: its channel, name and type.
    elements: Vec<(Channel<ElementMessage>, String, &'static str)>,
    tf: Option<Channel<FrameTransform>>,
    /// Patches written per wheel at the current sample.
    patch_count: Vec<u32>,
}

impl Recorder {
    fn create(
        path: &Path,
        scene: &Scene,
        model: &SimModel,
        sources: &BTreeMap<String, String>,
        run_to: f64,
    ) -> Result<Recorder, SimError> {
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(|e| SimError::Model {
                message: format!("cannot create the log directory {}: {e}", dir.display()),
            })?;
        }
        let mut header = LogHeader::new()
            .scene_entry("name", scene.name.clone())
            .scene_entry("source", scene.source.clone())
            .scene_entry("vehicle", scene.vehicle_file.display().to_string())
            .scene_entry("track", scene.track_file.display().to_string())
            .scene_entry("speed_m_s", format!("{}", scene.speed.speed_at(0.0)))
            .scene_entry("duration_s", format!("{}", scene.duration()))
            // where this run was to end: `duration_s` or an earlier end asked for
            // (`RunOptions::t_end`, `railsim run --duration-s`)
            .scene_entry("run_to_s", format!("{run_to}"))
            .scene_entry("contact_model", scene.contact.model.name())
            .scene_entry(
                "integrator",
                crate::scene::integrator_text(&scene.integrator),
            )
            .scene_entry("log_rate_hz", format!("{}", scene.log.rate_hz))
            .scene_entry("assessment_rate_hz", format!("{}", scene.assessment_rate()))
            .scene_entry("state_dim", format!("{}", model.dim()));
        if let Some(text) = sources.get("scene") {
            header = header.scene_toml(text.clone());
        }
        if !sources.is_empty() {
            header = header.metadata("railsim_sources", sources.clone());
        }
        let mut writer = LogWriter::create(path, &header, WriterOptions::default())?;
        // Channels of the chosen topics only (`[log] topics`): a reader lists no empty ones.
        let want = |t: Topic| scene.log.topics.contains(&t);
        let mut bodies = Vec::new();
        for mm in model.members.iter().filter(|_| want(Topic::Bodies)) {
            bodies.push(writer.channel::<BodyState>(&topics::body(&mm.name))?);
        }
        let mut contact = Vec::new();
        for w in model.wheels.iter().filter(|_| want(Topic::Contact)) {
            let side = match w.side {
                Side::Left => LogSide::Left,
                Side::Right => LogSide::Right,
            };
            contact
                .push(writer.channel::<PatchMessage>(&topics::contact(w.wheelset_number, side))?);
        }
        let mut wheelsets = Vec::new();
        for n in (0..model.wheels.len() / 2).filter(|_| want(Topic::Wheelsets)) {
            wheelsets.push(writer.channel::<WheelsetMessage>(&topics::wheelset(n as u32))?);
        }
        let mut carbody = Vec::new();
        if want(Topic::Carbody) {
            for (n, p) in model.comfort.iter().flat_map(|c| &c.1).enumerate() {
                carbody.push((
                    writer.channel::<CarbodyMessage>(&topics::carbody(n))?,
                    p.name.clone(),
                ));
            }
        }
        let mut bogie_frames = Vec::new();
        if want(Topic::BogieFrames) {
            for (n, (name, _)) in model.bogies.iter().flat_map(|b| &b.points).enumerate() {
                bogie_frames.push((
                    writer.channel::<BogieFrameMessage>(&topics::bogie_frame(n))?,
                    name.clone(),
                ));
            }
        }
        let mut elements = Vec::new();
        if want(Topic::Elements) {
            for el in &model.elements {
                elements.push((
                    writer.channel::<ElementMessage>(&topics::element(&el.name))?,
                    el.name.clone(),
                    el.law.type_name(),
                ));
            }
        }
        let tf = want(Topic::Tf)
            .then(|| writer.channel::<FrameTransform>(topics::TF))
            .transpose()?;
        Ok(Recorder {
            writer,
            bodies,
            contact,
            wheelsets,
            carbody,
            bogie_frames,
            elements,
            tf,
            patch_count: vec![0; model.wheels.len()],
        })
    }

    fn write(&mut self, model: &SimModel, ws: &Workspace, s: &Sample) -> Result<(), SimError> {
        let t_ns = s.t_ns;
        // a topic is written where it has channels (`create`: the scene's topics)
        if !self.bodies.is_empty() || self.tf.is_some() {
            for (i, mm) in model.members.iter().enumerate() {
                let k = &ws.kin[i];
                let q = k.q;
                let position = [mm.p0[0] + q[0], mm.p0[1] + q[1], mm.p0[2] + q[2]];
                let quat = quaternion(&rotation_rpy(q[3], q[4], q[5]));
                let msg = BodyState {
                    t_s: s.t,
                    name: mm.name.clone(),
                    position,
                    orientation: Quaternion {
                        x: quat[0],
                        y: quat[1],
                        z: quat[2],
                        w: quat[3],
                    },
                    velocity: mul_t(&k.frame, k.vel),
                    angular_velocity: mul_t(&k.frame, body_angular_velocity(mm, k)),
                };
                if let Some(channel) = self.bodies.get(i) {
                    self.writer.write(channel, t_ns, &msg)?;
                }
                if let Some(channel) = &self.tf {
                    let tf = FrameTransform::from_body(t_ns, "track", &msg);
                    self.writer.write(channel, t_ns, &tf)?;
                }
            }
        }
        if !self.contact.is_empty() {
            let count = &mut self.patch_count;
            count.fill(0);
            for p in &ws.patches {
                let w = &model.wheels[p.wheel];
                let r = &p.result;
                let c = log_creepages(r);
                let msg = PatchMessage {
                    t_s: s.t,
                    wheelset: w.wheelset_number,
                    side: match w.side {
                        Side::Left => LogSide::Left,
                        Side::Right => LogSide::Right,
                    },
                    patch: count[p.wheel],
                    y_rail_m: r.y_rail_profile,
                    y_wheel_m: r.y_wheel_profile,
                    contact_angle_rad: r.contact_angle,
                    penetration_m: r.penetration,
                    creepages: c,
                    fn_n: p.weight * r.forces.fn_,
                    fx_n: p.weight * r.forces.fx,
                    fy_n: p.weight * r.forces.fs,
                    mz_nm: p.weight * r.forces.mz,
                    wear_number_n: p.weight * patch_wear(r),
                    weight: (p.weight < 1.0).then_some(p.weight),
                };
                count[p.wheel] += 1;
                self.writer.write(&self.contact[p.wheel], t_ns, &msg)?;
            }
        }
        for ((channel, name), a) in self.carbody.iter().zip(&s.carbody) {
            let msg = CarbodyMessage {
                t_s: s.t,
                point: name.clone(),
                longitudinal_m_s2: a[0],
                lateral_m_s2: a[1],
                vertical_m_s2: a[2],
            };
            self.writer.write(channel, t_ns, &msg)?;
        }
        for ((channel, name), a) in self.bogie_frames.iter().zip(&s.bogie_frames) {
            let msg = BogieFrameMessage {
                t_s: s.t,
                point: name.clone(),
                longitudinal_m_s2: a[0],
                lateral_m_s2: a[1],
                vertical_m_s2: a[2],
            };
            self.writer.write(channel, t_ns, &msg)?;
        }
        for (((channel, name, kind), e), work) in
            self.elements.iter().zip(&s.elements).zip(&s.element_work)
        {
            let msg = ElementMessage {
                t_s: s.t,
                element: name.clone(),
                kind: (*kind).to_owned(),
                deflection_m: e.deflection,
                deflection_rate_m_s: e.rate,
                rotation_rad: e.rotation,
                force_n: e.force,
                moment_nm: e.moment,
                state_m: (e.states > 0).then(|| e.state[..e.states].to_vec()),
                sliding_force_n: e.sliding_force,
                sliding_moment_nm: e.sliding_moment,
                power_w: e.power,
                dissipation_w: e.dissipation,
                work_j: work[0],
                dissipated_j: work[1],
            };
            self.writer.write(channel, t_ns, &msg)?;
        }
        if !self.wheelsets.is_empty() {
            for msg in &s.wheelsets {
                self.writer
                    .write(&self.wheelsets[msg.wheelset as usize], t_ns, msg)?;
            }
        }
        Ok(())
    }

    /// Close the log with its `railsim_result` record: the state digest, the end time and how
    /// the run ended (`outcome` = `finished`, `stopped` with `stop_t_s`, `stop_body` and
    /// `stop_quantity`, or `failed` with `message`; docs/formats/log.md).
    fn finish(
        mut self,
        digest: u64,
        t_end: f64,
        error: Option<&SimError>,
    ) -> Result<LogStats, SimError> {
        let mut m = BTreeMap::new();
        m.insert("state_digest".to_owned(), format!("{digest:016x}"));
        m.insert("t_end_s".to_owned(), format!("{t_end:?}"));
        match error {
            None => {
                m.insert("outcome".to_owned(), "finished".to_owned());
            }
            Some(SimError::Stopped {
                t, body, quantity, ..
            }) => {
                m.insert("outcome".to_owned(), "stopped".to_owned());
                m.insert("stop_t_s".to_owned(), format!("{t:?}"));
                m.insert("stop_body".to_owned(), body.clone());
                m.insert("stop_quantity".to_owned(), quantity.clone());
            }
            Some(other) => {
                m.insert("outcome".to_owned(), "failed".to_owned());
                m.insert("message".to_owned(), other.to_string());
            }
        }
        self.writer.write_metadata("railsim_result", m)?;
        Ok(self.writer.finish()?)
    }
}

/// \[rad/s\] a member's absolute angular velocity, a wheelset's with its spin about the axle
/// (its kinematics keep the spin apart: `MemberKin::omega` is the non-spinning axle frame's).
fn body_angular_velocity(mm: &MemberModel, k: &MemberKin) -> V3 {
    if !mm.is_wheelset() {
        return k.omega;
    }
    let axle = [k.orient[0][1], k.orient[1][1], k.orient[2][1]];
    add(k.omega, scale(k.qd[4], axle))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A scene the format accepts, `rk4` at 1 µs for 11 s, is not cut short by a step limit:
    /// the integrator's default (10 million steps) would stop it at 10 s.
    #[test]
    fn a_long_run_of_small_steps_has_no_step_limit() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
        let scene = Scene::from_toml_str(
            r#"
            vehicle = "vehicles/wheelset_free.toml"
            track = "tracks/straight.toml"
            speed_kmh = 50
            duration_s = 11
            [integrator]
            method = "rk4"
            step_s = 1e-6
            "#,
            "test.toml",
            &root,
        )
        .unwrap_or_else(|e| panic!("{e}"));
        let sim = Simulation::new(&scene).unwrap_or_else(|e| panic!("{e}"));
        let steps = (scene.duration() / 1e-6).ceil() as usize;
        assert!(sim.integ.max_steps() > steps, "{}", sim.integ.max_steps());
    }
}
