//! Running stability (hunting): the critical speed of a vehicle on straight track, by the two
//! methods of nonlinear vehicle dynamics.
//!
//! - **Ramp-down** ([`ramp_down`]): the vehicle is disturbed at a speed where it hunts, runs
//!   there until the motion has settled into its limit cycle, and is then slowed down slowly;
//!   the hunting amplitude against speed is the stable branch of the bifurcation diagram, and
//!   the speed at which the amplitude falls below a threshold is the **nonlinear critical
//!   speed**: the lowest speed at which a stable hunting orbit exists. This is the method True
//!   and Polach recommend, because the Hopf bifurcation of a railway vehicle is usually
//!   subcritical, so the orbit survives below the speed at which small disturbances start to
//!   grow (True, *Multiple attractors and critical parameters and how to find them
//!   numerically*, Vehicle System Dynamics 51(3), 2013; Polach, *On non-linear methods of bogie
//!   stability assessment using computer simulations*, Proc. IMechE F 220, 2006). The
//!   threshold must lie below the smallest cycle: where the conicity falls with the amplitude a
//!   small tread cycle can outlive the large flange-contact one (the Manchester vehicle with
//!   `stripes`: 0.2–0.37 mm down to 216 km/h, the large cycle's fold at 258 km/h), so the end
//!   of a second, larger threshold's branch is reported beside it. The motion before the ramp
//!   must be a limit cycle, not a decaying transient ([`SUSTAINED_RATE`]).
//! - **Bisection on the growth rate** ([`bisect_growth`]): runs at constant speed from a small
//!   disturbance; the growth rate of the oscillation's amplitude ([`growth_rate`]) changes sign
//!   at the speed where this disturbance neither grows nor decays (for a small disturbance and a
//!   smooth contact, the linear critical speed of the Hopf bifurcation).
//!
//! Amplitudes are taken per half wave ([`half_cycles`]): the largest lateral excursion of a
//! wheelset from the track centre line between two consecutive crossings of it, refined by the
//! parabola through the largest sample and its neighbours. Crossings count with a hysteresis
//! (`floor`), so that noise near the centre line makes none, and the rebounds of flange impacts
//! at the top of a hunting swing, which do not cross the centre line, stay inside their half
//! wave (counted between turning points, a hunting swing at 400 km/h made three "half cycles"
//! per half period on the Manchester vehicle, two of them rebounds of about 1 mm).
//!
//! The studies run copies of a compiled scene with their own speed, length and disturbance
//! ([`Scene::study`]), without a log unless one is asked for; the vehicle, track, contact model
//! and integrator are the scene's.

use crate::error::SimError;
use crate::run::{RunOptions, RunSummary, Simulation};
use crate::scene::{RunLength, STRAIGHT_CURVATURE, Scene, SpeedProfile, extent};

/// One half wave of an oscillation about its centre line: the largest excursion between two
/// consecutive crossings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HalfCycle {
    /// \[s\] time of the largest excursion.
    pub t: f64,
    /// \[m\] the largest excursion from the centre line (absolute value).
    pub amplitude: f64,
}

/// The half waves of a sampled signal `y(t)` (samples in time order) about the centre line
/// `centre`: one per stretch between two consecutive crossings, with its largest excursion
/// refined by the parabola through that sample and its neighbours. A crossing counts when the
/// signal passes from more than `floor` on one side to more than `floor` on the other (the same
/// unit as `y`), so that noise near the centre line makes no crossings; reversals that do not
/// cross it (a flange impact's rebound at the top of a hunting swing) stay inside their half
/// wave. The stretches before the first and after the last crossing are not whole and give none.
pub fn half_cycles(t: &[f64], y: &[f64], centre: f64, floor: f64) -> Vec<HalfCycle> {
    let n = t.len().min(y.len());
    let mut out = Vec::new();
    // side: +1 above centre + floor, -1 below centre - floor, 0 not yet known
    let mut side = 0i8;
    // the current half wave's largest excursion (sample index); None before the first crossing
    let mut peak: Option<usize> = None;
    let peak_value = |i: usize| -> (f64, f64) {
        let d = |k: usize| (y[k] - centre).abs();
        if i == 0 || i + 1 >= n {
            return (t[i], d(i));
        }
        // parabola through the excursions at i - 1, i, i + 1
        let (h0, h1) = (t[i] - t[i - 1], t[i + 1] - t[i]);
        let (d0, d1) = ((d(i) - d(i - 1)) / h0, (d(i + 1) - d(i)) / h1);
        let c = (d1 - d0) / (h0 + h1); // half the second derivative
        if c >= 0.0 || !c.is_finite() {
            return (t[i], d(i));
        }
        let slope = d0 + c * h0; // the parabola's slope at t[i]
        let dt = (-slope / (2.0 * c)).clamp(-h0, h1);
        (t[i] + dt, d(i) + slope * dt + c * dt * dt)
    };
    for i in 0..n {
        let e = y[i] - centre;
        let now = if e > floor {
            1
        } else if e < -floor {
            -1
        } else {
            side
        };
        if now != side {
            if side != 0 {
                // a crossing: the half wave before it is whole if one began at a crossing
                if let Some(k) = peak {
                    let (tp, a) = peak_value(k);
                    out.push(HalfCycle {
                        t: tp,
                        amplitude: a,
                    });
                }
                peak = Some(i);
            }
            side = now;
        } else if let Some(k) = peak
            && e.abs() > (y[k] - centre).abs()
        {
            peak = Some(i);
        }
    }
    out
}

/// \[1/s\] growth rate of an oscillation from its half cycles: the least-squares slope of the
/// logarithm of the amplitude against time, over the half cycles at `t >= t_from`. `None` with
/// fewer than four such half cycles or a zero amplitude among them. For `A e^{σt} sin(ωt)` it
/// is σ.
pub fn growth_rate(cycles: &[HalfCycle], t_from: f64) -> Option<f64> {
    let c: Vec<(f64, f64)> = cycles
        .iter()
        .filter(|c| c.t >= t_from)
        .map(|c| (c.t, c.amplitude.ln()))
        .collect();
    if c.len() < 4 || c.iter().any(|p| !p.1.is_finite()) {
        return None;
    }
    let n = c.len() as f64;
    let (mt, ml) = c
        .iter()
        .fold((0.0, 0.0), |a, p| (a.0 + p.0 / n, a.1 + p.1 / n));
    let (sxy, sxx) = c.iter().fold((0.0, 0.0), |a, p| {
        (a.0 + (p.0 - mt) * (p.1 - ml), a.1 + (p.0 - mt).powi(2))
    });
    (sxx > 0.0).then(|| sxy / sxx)
}

/// Hysteresis of the centre-line crossings in a ramp-down, as a fraction of its threshold.
pub const RAMP_FLOOR: f64 = 0.2;

/// The lateral displacement of every wheelset at the samples of a run: times, and per
/// wheelset (numbered from the front) the displacements.
struct Traces {
    t: Vec<f64>,
    y: Vec<Vec<f64>>,
}

/// The studies measure the oscillation about the track centre line: the whole run must be on
/// straight track (irregularities allowed). Checked every 1 m from the rearmost wheelset's start
/// to the leading wheelset's end.
fn check_straight(study: &Scene, what: &str) -> Result<(), SimError> {
    let (_, x_max, x_min) = extent(&study.vehicle);
    let (a, b) = (study.start + x_min, study.start + study.distance() + x_max);
    let n = (b - a).ceil().max(1.0) as usize;
    for k in 0..=n {
        let s = a + (b - a) * k as f64 / n as f64;
        let f = study.track.frame_at(s);
        if f.curvature.abs() > STRAIGHT_CURVATURE {
            return Err(SimError::Study {
                message: format!(
                    "{what}: the run reaches a curve (radius {:.0} m at s = {s:.1} m on track '{}'); the study measures hunting about the centre line of straight track: use a straight track or a shorter run",
                    1.0 / f.curvature.abs(),
                    study.track_file.display()
                ),
            });
        }
    }
    Ok(())
}

/// Run `scene` with `opts`, keeping the wheelsets' lateral displacements at the samples.
fn run_traces(
    scene: &Scene,
    opts: &RunOptions,
    progress: &mut dyn FnMut(f64, f64),
) -> Result<(Traces, RunSummary), SimError> {
    let mut sim = Simulation::new(scene)?;
    let mut tr = Traces {
        t: Vec::new(),
        y: Vec::new(),
    };
    let summary = sim.run(scene, opts, progress, &mut |s| {
        if tr.y.is_empty() {
            tr.y = vec![Vec::new(); s.lateral.len()];
        }
        tr.t.push(s.t);
        for (v, y) in tr.y.iter_mut().zip(&s.lateral) {
            v.push(*y);
        }
    })?;
    Ok((tr, summary))
}

/// A ramp-down study: speeds, distances and the disturbance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RampDown {
    /// \[m/s\] speed at which the vehicle is disturbed and should hunt.
    pub v_start: f64,
    /// \[m/s\] speed at the end of the ramp (below the critical speed sought).
    pub v_end: f64,
    /// \[m\] distance run at `v_start` before the ramp: the disturbance grows into the limit
    /// cycle.
    pub settle: f64,
    /// \[m\] length of the ramp; the speed falls linearly with distance over it.
    pub ramp: f64,
    /// \[m\] lateral offset of the leading wheelset at t = 0.
    pub offset: f64,
    /// \[m\] hunting amplitude below which a wheelset counts as not hunting: the nonlinear
    /// critical speed's. It should be below the smallest limit cycle of interest: on the
    /// Manchester vehicle with `stripes` a tread-contact cycle of 0.2–0.37 mm exists some 40 km/h
    /// below the fold of the flange-contact cycle (docs/validation.md §8).
    pub threshold: f64,
    /// \[m\] a second, larger amplitude whose branch is reported by itself
    /// ([`RampResult::large_cycle_to`]): where the large (flange-contact) cycle ends. At least
    /// `threshold`.
    pub large_threshold: f64,
}

/// \[1/s\] the slowest decay of the amplitude before the ramp that still counts as a limit cycle
/// at the start speed ([`RampResult::rate_at_start`]): a decaying transient ramped down would
/// otherwise be reported as a critical speed. Near the critical speed a small disturbance
/// decays at some 0.5/s (the Manchester vehicle 5 km/h below it).
pub const SUSTAINED_RATE: f64 = -0.25;

/// Half cycles before the ramp over which [`RampResult::rate_at_start`] is taken.
const START_CYCLES: usize = 8;

/// One half cycle of one wheelset during a study, with the speed at its time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BranchPoint {
    /// \[s\] time of the half wave's largest excursion.
    pub t: f64,
    /// \[m/s\] speed at that time.
    pub speed: f64,
    /// \[m\] amplitude.
    pub amplitude: f64,
}

/// What a ramp-down finds.
#[derive(Debug, Clone)]
pub struct RampResult {
    /// Per wheelset (numbered from the front): its half cycles in time order, those of the
    /// settling run included.
    pub branch: Vec<Vec<BranchPoint>>,
    /// \[s\] time at which the ramp starts.
    pub ramp_start: f64,
    /// \[m\] largest amplitude of any wheelset in the last whole cycle before the ramp: the
    /// limit cycle at `v_start` (0 when it has none).
    pub amplitude_at_start: f64,
    /// \[1/s\] the growth rate ([`growth_rate`]) of the last half cycles before the ramp of the
    /// wheelset with the largest amplitude there; `None` with fewer than four.
    pub rate_at_start: Option<f64>,
    /// Whether the vehicle hunts at `v_start`: a wheelset's amplitude before the ramp reaches
    /// the threshold and does not decay faster than [`SUSTAINED_RATE`].
    pub hunting_at_start: bool,
    /// \[m/s\] the nonlinear critical speed: the speed of the last half cycle of the ramp in
    /// which some wheelset's amplitude reaches the threshold. `None` when the vehicle does not
    /// hunt at `v_start` ([`RampResult::hunting_at_start`]; start faster, or disturb more).
    pub critical_speed: Option<f64>,
    /// \[m/s\] the same for [`RampDown::large_threshold`]: where the large cycle ends (`None`
    /// when no half cycle of the ramp reaches it).
    pub large_cycle_to: Option<f64>,
    /// Whether a wheelset still reached the threshold in the last cycle of the ramp (the
    /// critical speed is then at or below `v_end`).
    pub hunting_at_end: bool,
    /// EN 14363's stability criterion along the run (`crate::assess`): per 100 m window of the
    /// sliding r.m.s. of the band-passed track-shift force, the speed at its end and the
    /// largest ratio of any axle's r.m.s. to its limit.
    pub sum_y_rms: Vec<SpeedRatio>,
    /// \[m/s\] the lowest speed at the end of a window of the ramp in which some axle's
    /// r.m.s. exceeds its limit; `None` when none does during the ramp.
    pub sum_y_rms_exceeded_to: Option<f64>,
    /// The run's summary.
    pub summary: RunSummary,
}

/// A ratio to a limit at a speed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpeedRatio {
    /// \[m/s\]
    pub speed: f64,
    /// \[-\]
    pub ratio: f64,
}

/// The ramp-down study of `ramp` on `scene` (the scene's vehicle, track from its start,
/// contact, integrator and log settings; its speed, length and disturbance replaced), run with
/// `opts` (`no_log` for none): see the module docs.
pub fn ramp_down(
    scene: &Scene,
    ramp: &RampDown,
    opts: &RunOptions,
    progress: &mut dyn FnMut(f64, f64),
) -> Result<RampResult, SimError> {
    let bad = |what: String| SimError::Study {
        message: format!("ramp-down study: {what}"),
    };
    if !(ramp.v_start > ramp.v_end && ramp.v_end > 0.0) {
        return Err(bad(format!(
            "the start speed ({:.2} m/s) must be above the end speed ({:.2} m/s), both positive",
            ramp.v_start, ramp.v_end
        )));
    }
    if !(ramp.settle > 0.0 && ramp.ramp > 0.0 && ramp.threshold > 0.0) {
        return Err(bad(format!(
            "the settling distance ({} m), the ramp length ({} m) and the threshold ({} m) must be positive",
            ramp.settle, ramp.ramp, ramp.threshold
        )));
    }
    if !(ramp.large_threshold >= ramp.threshold && ramp.large_threshold.is_finite()) {
        return Err(bad(format!(
            "the large cycle's threshold ({} m) must be at least the threshold ({} m)",
            ramp.large_threshold, ramp.threshold
        )));
    }
    let speed = SpeedProfile::from_points(
        vec![0.0, ramp.settle, ramp.settle + ramp.ramp],
        vec![ramp.v_start, ramp.v_start, ramp.v_end],
    )
    .ok_or_else(|| bad("the speed profile is not valid".into()))?;
    let ramp_start = speed.time_at(ramp.settle);
    let study = scene.study(
        speed,
        RunLength::Distance(ramp.settle + ramp.ramp),
        ramp.offset,
    )?;
    check_straight(&study, "ramp-down study")?;
    let (tr, summary) = run_traces(&study, opts, progress)?;
    let speed_at = |t: f64| study.speed.speed_at(study.speed.distance_at(t));
    let branch: Vec<Vec<BranchPoint>> =
        tr.y.iter()
            .map(|y| {
                half_cycles(&tr.t, y, 0.0, RAMP_FLOOR * ramp.threshold)
                    .into_iter()
                    .map(|c| BranchPoint {
                        t: c.t,
                        speed: speed_at(c.t),
                        amplitude: c.amplitude,
                    })
                    .collect()
            })
            .collect();
    // the limit cycle at the start, per wheelset: its last half cycles before the ramp (the
    // last two give the amplitude, all of them the growth rate)
    let before: Vec<Vec<HalfCycle>> = branch
        .iter()
        .map(|b| {
            let mut v: Vec<HalfCycle> = b
                .iter()
                .rev()
                .filter(|p| p.t < ramp_start)
                .take(START_CYCLES)
                .map(|p| HalfCycle {
                    t: p.t,
                    amplitude: p.amplitude,
                })
                .collect();
            v.reverse();
            v
        })
        .collect();
    let start_amplitude = |c: &[HalfCycle]| {
        c.iter()
            .rev()
            .take(2)
            .map(|p| p.amplitude)
            .fold(0.0, f64::max)
    };
    let amplitude_at_start = before
        .iter()
        .map(|c| start_amplitude(c))
        .fold(0.0, f64::max);
    // ... and whether it is one: the wheelset with the largest amplitude there does not decay
    let rate_at_start = before
        .iter()
        .max_by(|a, b| start_amplitude(a).total_cmp(&start_amplitude(b)))
        .and_then(|c| growth_rate(c, f64::NEG_INFINITY));
    let hunting_at_start =
        amplitude_at_start >= ramp.threshold && rate_at_start.is_some_and(|r| r >= SUSTAINED_RATE);
    let last_at = |level: f64| {
        branch
            .iter()
            .filter_map(|b| {
                b.iter()
                    .filter(|p| p.t >= ramp_start && p.amplitude >= level)
                    .map(|p| p.speed)
                    .reduce(f64::min)
            })
            .reduce(f64::min)
    };
    let critical_speed = last_at(ramp.threshold).filter(|_| hunting_at_start);
    let large_cycle_to = last_at(ramp.large_threshold);
    let hunting_at_end = hunting_at_start
        && branch.iter().any(|b| {
            b.iter()
                .rev()
                .take(2)
                .any(|p| p.t >= ramp_start && p.amplitude >= ramp.threshold)
        });
    // EN 14363's criterion per window (the windows of all axles end at the same distances)
    let axles = &summary.assessment.axles;
    let sum_y_rms: Vec<SpeedRatio> = axles.first().map_or(Vec::new(), |first| {
        (0..first.sum_y_rms_windows.len())
            .map(|k| SpeedRatio {
                speed: study.speed.speed_at(first.sum_y_rms_windows[k].end),
                ratio: axles
                    .iter()
                    .filter_map(|a| a.sum_y_rms_windows.get(k).map(|w| w.value / a.rms_limit()))
                    .fold(0.0, f64::max),
            })
            .collect()
    });
    let sum_y_rms_exceeded_to = sum_y_rms
        .iter()
        .filter(|w| w.ratio > 1.0 && w.speed < ramp.v_start)
        .map(|w| w.speed)
        .reduce(f64::min);
    Ok(RampResult {
        branch,
        ramp_start,
        amplitude_at_start,
        rate_at_start,
        hunting_at_start,
        critical_speed,
        large_cycle_to,
        hunting_at_end,
        sum_y_rms,
        sum_y_rms_exceeded_to,
        summary,
    })
}

/// The growth of a small disturbance at one constant speed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Growth {
    /// \[m/s\]
    pub speed: f64,
    /// \[1/s\] the largest growth rate of any wheelset ([`growth_rate`] of its half cycles
    /// after the first tenth of the run); `None` when no wheelset had four half cycles.
    pub rate: Option<f64>,
    /// \[1/s\] the same over the second half of the run only, once the wheelsets that started
    /// at rest move with the disturbed one (what [`bisect_growth`] uses).
    pub late_rate: Option<f64>,
    /// \[m\] the largest amplitude of any wheelset's last half cycle.
    pub last_amplitude: f64,
}

/// Run `scene` at constant `speed` \[m/s\] for `duration` \[s\] from a lateral `offset` \[m\]
/// of the leading wheelset and measure the growth of the oscillation.
pub fn growth_at(
    scene: &Scene,
    speed: f64,
    duration: f64,
    offset: f64,
) -> Result<Growth, SimError> {
    let mut study = scene.study(
        SpeedProfile::constant(speed),
        RunLength::Duration(duration),
        offset,
    )?;
    check_straight(&study, "growth-rate run")?;
    // (the growth rate comes from the lateral displacements at the log's samples; the
    // assessment is not used)
    study.sample_at_log_rate();
    let opts = RunOptions {
        no_log: true,
        ..Default::default()
    };
    let (tr, _) = run_traces(&study, &opts, &mut |_, _| {})?;
    let (mut rate, mut late_rate): (Option<f64>, Option<f64>) = (None, None);
    let mut last_amplitude = 0.0f64;
    let max = |a: Option<f64>, b: Option<f64>| match (a, b) {
        (Some(a), Some(b)) => Some(a.max(b)),
        (a, b) => a.or(b),
    };
    for y in &tr.y {
        let c = half_cycles(&tr.t, y, 0.0, offset.abs() * 1e-4);
        rate = max(rate, growth_rate(&c, 0.1 * duration));
        late_rate = max(late_rate, growth_rate(&c, 0.5 * duration));
        if let Some(l) = c.last() {
            last_amplitude = last_amplitude.max(l.amplitude);
        }
    }
    Ok(Growth {
        speed,
        rate,
        late_rate,
        last_amplitude,
    })
}

/// What a bisection on the growth rate finds.
#[derive(Debug, Clone)]
pub struct Bisection {
    /// \[m/s\] the speed where the growth rate changes sign, interpolated linearly between the
    /// last bracket's rates.
    pub critical_speed: f64,
    /// Every run, in the order made.
    pub runs: Vec<Growth>,
}

/// Bisect the speed between `lo` and `hi` \[m/s\] on the sign of the growth rate of constant-
/// speed runs of `duration` \[s\] from a lateral `offset` \[m\] of the leading wheelset, until
/// the bracket is narrower than `rel_tol` of its upper end. The rate is that of the second half
/// of each run ([`Growth::late_rate`]): in a vehicle only the leading wheelset is disturbed, and
/// the others' motion first grows from rest whether the vehicle is stable or not (over the
/// whole run this made a 0.5 mm disturbance of the Manchester vehicle "grow" at 268.8 km/h,
/// where it decays once the vehicle moves as a whole); a run whose last half wave is more than
/// four times the offset counts as growing. Errors when a run measures no
/// growth rate or the rates at `lo` and `hi` do not bracket a change of sign (decay at `lo`,
/// growth at `hi`).
pub fn bisect_growth(
    scene: &Scene,
    (lo, hi): (f64, f64),
    duration: f64,
    offset: f64,
    rel_tol: f64,
    progress: &mut dyn FnMut(&Growth),
) -> Result<Bisection, SimError> {
    let bad = |what: String| SimError::Study {
        message: format!("growth-rate bisection: {what}"),
    };
    if !(lo > 0.0 && hi > lo && rel_tol > 0.0 && duration > 0.0 && offset != 0.0) {
        return Err(bad(format!(
            "expected 0 < lo < hi (found {lo} and {hi} m/s), a positive duration ({duration} s) and tolerance ({rel_tol}), and a non-zero offset ({offset} m)"
        )));
    }
    let mut runs = Vec::new();
    let mut eval = |v: f64, runs: &mut Vec<Growth>| -> Result<f64, SimError> {
        let g = growth_at(scene, v, duration, offset)?;
        progress(&g);
        runs.push(g);
        // A disturbance that died out before the second half (fewer than four half cycles
        // there, the last below the offset) decays: its rate over the whole run.
        let decayed = || {
            g.rate
                .filter(|r| *r < 0.0 && g.last_amplitude < offset.abs())
        };
        let rate = g.late_rate.or_else(decayed).ok_or_else(|| {
            bad(format!(
                "the run at {v:.2} m/s measured no growth rate (fewer than four half cycles after its first tenth, or in its second half without having decayed): run longer"
            ))
        })?;
        // A disturbance that has grown fourfold is unstable, whatever the sign of the rate of
        // a saturated cycle (near zero) says.
        Ok(if g.last_amplitude > 4.0 * offset.abs() {
            rate.max(f64::MIN_POSITIVE)
        } else {
            rate
        })
    };
    let (mut a, mut b) = (lo, hi);
    let (mut ga, mut gb) = (eval(a, &mut runs)?, eval(b, &mut runs)?);
    if !(ga < 0.0 && gb > 0.0) {
        let (aa, ab) = (runs[0].last_amplitude, runs[1].last_amplitude);
        return Err(bad(format!(
            "the growth rates {ga:.4}/s at {lo:.2} m/s and {gb:.4}/s at {hi:.2} m/s (last half-cycle amplitudes {:.3} and {:.3} mm) do not bracket a change from decay to growth; a rate near zero with an amplitude far above the offset is a limit cycle, which the ramp-down method measures",
            aa * 1e3,
            ab * 1e3
        )));
    }
    while b - a > rel_tol * b {
        let m = 0.5 * (a + b);
        let g = eval(m, &mut runs)?;
        if g < 0.0 {
            (a, ga) = (m, g);
        } else {
            (b, gb) = (m, g);
        }
    }
    Ok(Bisection {
        critical_speed: a + (b - a) * (-ga) / (gb - ga).max(f64::MIN_POSITIVE),
        runs,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn signal(f: impl Fn(f64) -> f64, dt: f64, t_end: f64) -> (Vec<f64>, Vec<f64>) {
        let t: Vec<f64> = (0..=(t_end / dt).round() as usize)
            .map(|k| k as f64 * dt)
            .collect();
        let y = t.iter().map(|&t| f(t)).collect();
        (t, y)
    }

    #[test]
    fn half_cycles_of_an_offset_sine_give_its_amplitude() {
        // 3 mm at 5.3 Hz about a 2 mm offset, sampled at 200 Hz (38 samples per period)
        let (t, y) = signal(
            |t| 2e-3 + 3e-3 * (2.0 * std::f64::consts::PI * 5.3 * t + 0.4).sin(),
            0.005,
            3.0,
        );
        let c = half_cycles(&t, &y, 2e-3, 1e-6);
        // 31.8 half periods in 3 s, the first and the last not whole
        assert!(c.len() == 30 || c.len() == 31, "{} half cycles", c.len());
        for h in &c {
            assert!(
                (h.amplitude / 3e-3 - 1.0).abs() < 1e-3,
                "amplitude {}",
                h.amplitude
            );
        }
        // half a period between half cycles
        let dt = (c[c.len() - 1].t - c[0].t) / (c.len() - 1) as f64;
        assert!((dt * 2.0 * 5.3 - 1.0).abs() < 1e-3, "half period {dt}");
    }

    #[test]
    fn growth_rate_of_a_growing_and_a_decaying_oscillation() {
        for sigma in [-0.8, -0.05, 0.3] {
            let (t, y) = signal(
                |t| 1e-3 * (sigma * t).exp() * (2.0 * std::f64::consts::PI * 4.0 * t).sin(),
                0.0025,
                4.0,
            );
            let g = growth_rate(&half_cycles(&t, &y, 0.0, 1e-9), 0.5).unwrap();
            assert!(
                (g - sigma).abs() < 0.01 * sigma.abs().max(0.1),
                "{g} vs {sigma}"
            );
        }
    }

    #[test]
    fn rebounds_and_ripples_make_no_half_cycles() {
        // A hunting-like swing, 6 mm at 5 Hz, with a third harmonic that puts two extra turning
        // points into every half wave (as a flange rebound does), and a 0.5 µm, 90 Hz ripple:
        // one half cycle per half period, of the swing's largest excursion.
        let w = 2.0 * std::f64::consts::PI * 5.0;
        let f = |t: f64| 6e-3 * (w * t).sin() + 1.5e-3 * (3.0 * w * t).sin();
        let (t, y) = signal(
            |t| f(t) + 0.5e-6 * (2.0 * std::f64::consts::PI * 90.0 * t).sin(),
            0.0005,
            2.0,
        );
        // crossings every 0.1 s from t = 0 (where the side is not yet known) to 2 s: 18 whole
        // half waves between the crossings at 0.1 .. 1.9 s
        let c = half_cycles(&t, &y, 0.0, 1e-6);
        assert_eq!(c.len(), 18, "{c:?}");
        // the largest excursion, max of 6 sin x + 1.5 sin 3x = sin x (10.5 - 6 sin² x), found
        // by sampling finely
        let peak = (0..100_000)
            .map(|k| f(k as f64 * 1e-6))
            .fold(0.0f64, f64::max);
        for h in &c {
            assert!(
                (h.amplitude - peak).abs() < 2e-6,
                "{} vs {peak}",
                h.amplitude
            );
        }
        // a flat signal has none, and three half cycles give no growth rate
        assert!(half_cycles(&t, &vec![1e-3; t.len()], 0.0, 1e-6).is_empty());
        assert!(growth_rate(&c[..3], 0.0).is_none());
    }
}
