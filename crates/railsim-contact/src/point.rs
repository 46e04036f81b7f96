//! Single-point contact search of the Hertz models (`polach`, `fastsim`, `linear`): one rigid
//! contact pair per penetrated zone, found without travelling the profiles.
//!
//! The broad phase ([`crate::broad`]) leaves the few pairs of short arcs where the rail can
//! touch or enter the wheel. Consecutive rail arcs form runs; in each run the deepest chord
//! estimate of the depth, and then every other local maximum of the estimates that may be deeper
//! than the minima already found or is separated from them by a dip of the estimates (one the
//! split rule below could separate), both allowing for the estimates' error, starts a Newton
//! search for the rigid contact pair: the isosceles pair (`f = 0`, `geometry` module docs) whose
//! tangents are parallel, i.e. the point where the gap along the pairs, `g(s_r)`, has
//! `g' = t_B × t_A = 0` (seed §3.2: the pair with θ_C = 90°). Newton runs on both conditions at
//! once with the exact derivatives of `f` and the curvature terms of the tangents, kept in a
//! bracket of `s_r` that is narrowed by the sign of `g'`, with fixed descent steps where `g` is
//! not convex.
//!
//! A minimum with a negative gap is a well; between neighbouring minima of one run the largest
//! gap is found by Newton again, for the maximum. Ripples are dropped and every well becomes a
//! zone carrying its share of the run (`crate::wells`, docs/models/contact.md §4.1). The result
//! has the same form as a travelling: one pair per zone and zones of one pair each, so the
//! Hertz patch frame is built as before.
//!
//! The same broad phase also restricts a cold travelling to windows around its candidates
//! (`travel_windows`).

use crate::broad::{BroadMemory, BroadScratch, Candidate, LEAF_THICK, candidates, recheck};
use crate::geometry::{
    IsoPair, PairEval, PoseCtx, RunEnd, TravelOptions, TravelStats, Zone, anchored_run, eval_pair,
    normal_and_gap, pair_at_rail, record, travel_error,
};
use crate::pair::WheelRailPair;
use crate::wells::{SHARE_MIN, drop_ripples, shares};

/// \[m\] Newton stops when both arc lengths move less than this.
const S_TOL: f64 = 1e-8;
/// \[m\] two minima closer than this on the rail are the same.
const SAME: f64 = 0.2e-3;
/// Most distinct minima in one run (more: the travelling takes over).
const MAX_MINIMA: usize = 6;
/// Most distinct estimated points in one run (more, or more than twice as many candidates: the
/// travelling takes over).
const MAX_PROFILE: usize = 64;
/// \[m\] the broad phase keeps arcs up to this far inside the wheel; a zone deeper than half of
/// it is handed to the travelling.
pub(crate) const BROAD_DEPTH: f64 = 0.5e-3;
/// \[m\] margin of the broad-phase queries a warm start keeps ([`BroadMemory`]): they serve
/// until some point of the wheel's locus has moved this far.
pub(crate) const WARM_MARGIN: f64 = 0.2e-3;

/// Find the rigid contact pair of every zone: pairs to `pairs`, one-pair zones to `zones`
/// (both cleared first); `scratch` holds the broad phase's buffers. `None` when the search
/// cannot vouch for its result (a minimum on the edge of its run, a zone deeper than half of
/// [`BROAD_DEPTH`], more minima or estimates in a run than it keeps): the caller travels instead.
///
/// With `memory` (a warm start, one per wheel) the broad phase reuses the leaf pairs of an
/// earlier query made with the margin [`WARM_MARGIN`] while they cover the pose, and makes and
/// stores such a query when they do not; in both cases the rules are then applied to the
/// stored pairs at this pose ([`recheck`]), so the result depends on the stored query only
/// through leaf pairs that pass the rules at this pose. `stats.warm` tells whether the stored
/// query was reused.
#[allow(clippy::too_many_arguments)]
pub(crate) fn search(
    pair: &WheelRailPair,
    ctx: &PoseCtx,
    travel: &TravelOptions,
    scratch: &mut BroadScratch,
    memory: Option<&mut BroadMemory>,
    pairs: &mut Vec<IsoPair>,
    zones: &mut Vec<Zone>,
) -> Option<TravelStats> {
    let mut stats = TravelStats::default();
    pairs.clear();
    zones.clear();
    match memory {
        None => candidates(pair, ctx, BROAD_DEPTH, 0.0, scratch),
        Some(m) => {
            stats.warm = m.covers(pair, ctx);
            if !stats.warm {
                candidates(pair, ctx, BROAD_DEPTH, WARM_MARGIN, scratch);
                if scratch.candidates.iter().any(|c| c.leaves[0] == u32::MAX) {
                    m.invalidate();
                    return None;
                }
                // stored along the rail, so that the rechecked candidates come sorted
                scratch
                    .candidates
                    .sort_unstable_by(|a, b| a.s_r[0].total_cmp(&b.s_r[0]));
                m.store(pair, ctx, WARM_MARGIN, &scratch.candidates);
            }
            if !recheck(pair, ctx, BROAD_DEPTH, m.leaves(), scratch) {
                m.invalidate();
                return None;
            }
        }
    }
    let cands = &mut scratch.candidates;
    // sorted along the rail (few candidates, mostly in order already: insertion sort)
    for i in 1..cands.len() {
        let mut j = i;
        while j > 0 && cands[j - 1].s_r[0] > cands[j].s_r[0] {
            cands.swap(j - 1, j);
            j -= 1;
        }
    }
    let mut i = 0;
    while i < cands.len() {
        let (j, _) = run_from(cands, i);
        run_minima(pair, ctx, travel, &cands[i..=j], pairs, zones, &mut stats)?;
        i = j + 1;
    }
    if pairs.iter().any(|p| p.gap < -0.5 * BROAD_DEPTH) {
        return None;
    }
    Some(stats)
}

/// The run of candidates (sorted along the rail) that starts at `i`: rail arcs that touch or
/// overlap. Returns the index of its last candidate and where its rail arcs end.
fn run_from(cands: &[Candidate], i: usize) -> (usize, f64) {
    let mut j = i;
    let mut end = cands[i].s_r[1];
    while j + 1 < cands.len() && cands[j + 1].s_r[0] <= end + 1e-9 {
        j += 1;
        end = end.max(cands[j].s_r[1]);
    }
    (j, end)
}

/// The zone(s) of one run of candidates (sorted by rail arc length).
fn run_minima(
    pair: &WheelRailPair,
    ctx: &PoseCtx,
    travel: &TravelOptions,
    run: &[Candidate],
    pairs: &mut Vec<IsoPair>,
    zones: &mut Vec<Zone>,
    stats: &mut TravelStats,
) -> Option<()> {
    let lo = (run[0].s_r[0] - 1e-3).max(0.0);
    let hi = (run.iter().fold(0.0f64, |m, c| m.max(c.s_r[1])) + 1e-3).min(pair.rail.length());
    // The estimates as a profile along the rail: one entry per estimated rail point (the
    // deepest of its candidates), sorted.
    // (the candidates' estimates sorted by rail arc length, then by candidate; equal points
    // merged into the deepest, the first of equals)
    if run.len() > 2 * MAX_PROFILE {
        return None;
    }
    let mut prof = [(0.0f64, 0.0f64, 0usize); 2 * MAX_PROFILE];
    for (k, c) in run.iter().enumerate() {
        prof[k] = (c.s_r_est, c.depth, k);
    }
    let prof = &mut prof[..run.len()];
    prof.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.2.cmp(&b.2)));
    let mut m = 0;
    for i in 0..prof.len() {
        let e = prof[i];
        if m > 0 && (e.0 - prof[m - 1].0).abs() < 1e-9 {
            if e.1 > prof[m - 1].1 {
                prof[m - 1] = e;
            }
        } else {
            prof[m] = e;
            m += 1;
        }
    }
    if m > MAX_PROFILE {
        return None;
    }
    let prof = &prof[..m];
    // Newton from the local maxima of the profile, deepest first; every well of the run carries
    // a share of its Hertz solution (`crate::wells`), so every peak at least 1 mm from the
    // minima found is searched (a Newton search from a peak on the flank of a found well ends
    // on that well). Wells less prominent than the estimates resolve can be missed; their
    // shares are small (`tests/point_search.rs`).
    let mut mins = [IsoPair::default(); MAX_MINIMA];
    let mut n = 0;
    // deepest first, the later of equals first
    let mut order = [0u8; MAX_PROFILE];
    for (j, o) in order[..m].iter_mut().enumerate() {
        *o = j as u8;
    }
    let order = &mut order[..m];
    order.sort_unstable_by(|&a, &b| {
        prof[b as usize]
            .1
            .total_cmp(&prof[a as usize].1)
            .then(b.cmp(&a))
    });
    let err = 0.25 * LEAF_THICK + 1e-6;
    for &j in order.iter() {
        let j = j as usize;
        let (s_j, d_j, k) = prof[j];
        let peak = (j == 0 || prof[j - 1].1 <= d_j) && (j + 1 == m || prof[j + 1].1 <= d_j);
        // outside the wheel by more than the estimates' error: no zone (and no deeper peak)
        if d_j + err < 0.0 {
            break;
        }
        let wanted = mins[..n].iter().all(|q| (q.s_r - s_j).abs() >= 1e-3);
        if !peak || !wanted {
            continue;
        }
        let c = &run[k];
        let Some((e, s_w, s_r)) =
            local_min(pair, ctx, travel, c, lo, hi, &mins[..n], stats).ok()?
        else {
            continue;
        };
        let p = record(&e, s_w, s_r, travel_error(&e));
        if mins[..n].iter().all(|m| (m.s_r - p.s_r).abs() >= SAME) {
            if n == MAX_MINIMA {
                return None;
            }
            mins[n] = p;
            n += 1;
        }
    }
    let mins = &mut mins[..n];
    mins.sort_by(|a, b| a.s_r.total_cmp(&b.s_r));
    // The wells: the interpenetrating minima, and between neighbours the largest gap (Newton from
    // the shallowest estimate in between), as depths; then their shares.
    let mut depth = [0.0f64; MAX_MINIMA];
    let mut well = [0usize; MAX_MINIMA];
    let mut hump = [0.0f64; MAX_MINIMA];
    let mut nw = 0;
    for (k, q) in mins.iter().enumerate().filter(|(_, m)| m.gap < 0.0) {
        if nw > 0 {
            let p = &mins[well[nw - 1]];
            let start = run
                .iter()
                .filter(|c| c.s_r_est > p.s_r && c.s_r_est < q.s_r)
                .min_by(|a, b| a.depth.total_cmp(&b.depth))
                .map_or(0.5 * (p.s_r + q.s_r), |c| c.s_r_est);
            let f = (start - p.s_r) / (q.s_r - p.s_r);
            let s_w0 = p.s_w + f * (q.s_w - p.s_w);
            let (e, _, _, _) = extremum(
                pair,
                ctx,
                travel,
                start,
                s_w0,
                p.s_r,
                q.s_r,
                -1.0,
                &[],
                stats,
            );
            hump[nw - 1] = (-normal_and_gap(&e).1).max(0.0);
        }
        depth[nw] = -q.gap;
        well[nw] = k;
        nw += 1;
    }
    let nw = drop_ripples(&mut depth, &mut well, &mut hump, nw);
    let mut share = [0.0f64; MAX_MINIMA];
    shares(
        &depth[..nw],
        &hump[..nw.saturating_sub(1)],
        &mut share[..nw],
    );
    for k in 0..nw {
        if share[k] < SHARE_MIN {
            continue;
        }
        zones.push(Zone {
            first: pairs.len(),
            last: pairs.len(),
            deepest: pairs.len(),
            share: share[k],
        });
        pairs.push(mins[well[k]]);
    }
    Some(())
}

/// Newton search for the local minimum of the gap along the isosceles pairs from the estimate
/// `c`, with the rail arc length kept in `[lo, hi]`. Returns the pair and its arc lengths, or
/// `Err` if Newton did not converge or the minimum lies on the edge of `[lo, hi]` with a
/// negative gap; `Ok(None)` if the iterates reach one of the minima `known`.
#[allow(clippy::too_many_arguments)]
fn local_min(
    pair: &WheelRailPair,
    ctx: &PoseCtx,
    travel: &TravelOptions,
    c: &Candidate,
    lo: f64,
    hi: f64,
    known: &[IsoPair],
    stats: &mut TravelStats,
) -> Result<Option<(PairEval, f64, f64)>, ()> {
    let (e, s_w, s_r, found) = extremum(
        pair, ctx, travel, c.s_r_est, c.s_w_est, lo, hi, 1.0, known, stats,
    );
    // A minimum on the edge of the run: beyond it no arc can touch (no candidates), so with a
    // positive gap there is no zone here; with a negative one the zone reaches past the run
    // (deeper than the broad phase's depth): leave it to the travelling.
    let on_edge = s_r - lo < 1e-6 || hi - s_r < 1e-6;
    match found {
        Found::Known => Ok(None),
        Found::NotConverged => Err(()),
        Found::Converged if on_edge && normal_and_gap(&e).1 < 0.0 => Err(()),
        Found::Converged => Ok(Some((e, s_w, s_r))),
    }
}

/// How a Newton search ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Found {
    Converged,
    /// within 50 µm of a known extremum
    Known,
    NotConverged,
}

/// Newton search for a local minimum (`sign` = 1) or maximum (`sign` = -1) of the gap along the
/// isosceles pairs from (`s_r`, `s_w`), with `s_r` kept in `[lo, hi]`, stopped early when an
/// iterate comes within 50 µm of a pair in `known` after a short step; the pair is isosceles to
/// the travelling's tolerance. Returns the pair, its arc lengths and how the search ended.
#[allow(clippy::too_many_arguments)]
fn extremum(
    pair: &WheelRailPair,
    ctx: &PoseCtx,
    travel: &TravelOptions,
    mut s_r: f64,
    mut s_w: f64,
    mut lo: f64,
    mut hi: f64,
    sign: f64,
    known: &[IsoPair],
    stats: &mut TravelStats,
) -> (PairEval, f64, f64, Found) {
    let mut found = Found::NotConverged;
    let l_w = pair.wheel.length();
    s_r = s_r.clamp(lo, hi);
    let mut e = eval_pair(pair, ctx, s_w, s_r);
    stats.pairs += 1;
    for _ in 0..24 {
        let (ta, tb) = (e.a.t, e.b.t);
        let tab = ta[0] * tb[0] + ta[1] * tb[1];
        // g' along the pairs: the sine of the angle between the tangents
        let g1 = tb[0] * ta[1] - tb[1] * ta[0];
        let sp = e.a.speed;
        // derivatives of f and g' (per unit profile arc of the wheel, per unit rail arc)
        let f_w = e.dfdw * sp;
        let f_r = e.dfdw - e.dfds;
        let g_w = e.a.kappa * tab * sp;
        let g_r = -e.b.kappa * tab;
        if f_w.abs() < 1e-12 {
            break;
        }
        // f = 0 solved for s_w at fixed s_r, and how s_w follows s_r along f = 0
        let dw0 = -e.f / f_w;
        let dw_dr = -f_r / f_w;
        // g' and its derivative along the pairs (of -g for a maximum)
        let h = sign * (g1 + g_w * dw0);
        let hp = sign * (g_r + g_w * dw_dr);
        if h < 0.0 {
            lo = lo.max(s_r);
        } else {
            hi = hi.min(s_r);
        }
        let mut dr = if hp > 1e-3 {
            (-h / hp).clamp(-4e-3, 4e-3)
        } else {
            -h.signum() * 0.5e-3
        };
        if !(s_r + dr > lo && s_r + dr < hi) {
            dr = 0.5 * (lo + hi) - s_r;
        }
        let dw = dw0 + dw_dr * dr;
        s_r += dr;
        s_w = (s_w + dw.clamp(-2e-3, 2e-3)).clamp(0.0, l_w);
        e = eval_pair(pair, ctx, s_w, s_r);
        stats.pairs += 1;
        if (dr.abs() < S_TOL && dw.abs() < S_TOL) || hi - lo < S_TOL {
            found = Found::Converged;
            break;
        }
        if dr.abs() < 0.5e-3 && known.iter().any(|m| (m.s_r - s_r).abs() < 50e-6) {
            return (e, s_w, s_r, Found::Known);
        }
    }
    let chord = ((e.b.p[0] - e.a.p[1]).powi(2) + (e.b.p[1] - e.a.p[2]).powi(2)).sqrt();
    if e.f.abs() > travel.angle_tol * chord.max(1e-9) {
        let (e1, s_w1, _) = pair_at_rail(pair, ctx, travel, s_r, s_w, stats);
        e = e1;
        s_w = s_w1;
    }
    (e, s_w, s_r, found)
}

/// The cold travelling restricted to windows around the broad phase's candidates
/// (`docs/models/contact.md` §3.1): the rail-anchored pairs of the travelling (nodes `k * step`
/// and their dyadic midpoints) from two nodes before to two nodes after every run of candidate
/// rail arcs (windows that meet or touch merged), as a warm start travels its windows, to `out`
/// (cleared first). Every zone lies in candidates (every interpenetrating pair down to the broad
/// phase's depth does; a deeper zone's edges do), so the zones, their pairs and two nodes on each side are those of the full
/// travelling up to where the pairs' Newton iterations started. Returns `false` (and the caller
/// travels the whole profile) when there are no candidates (no contact: the full travelling
/// reports the gaps), a profile's end lies in a window, a window begins or ends inside the wheel
/// (a zone deeper than the broad phase's depth reaches past it), or there are more than 16
/// windows.
pub(crate) fn travel_windows(
    pair: &WheelRailPair,
    ctx: &PoseCtx,
    opts: &TravelOptions,
    scratch: &mut BroadScratch,
    out: &mut Vec<IsoPair>,
    stats: &mut TravelStats,
) -> bool {
    out.clear();
    *stats = TravelStats::default();
    candidates(pair, ctx, BROAD_DEPTH, 0.0, scratch);
    let cands = &mut scratch.candidates;
    if cands.is_empty() || cands.iter().any(|c| c.leaves[0] == u32::MAX) {
        return false;
    }
    cands.sort_unstable_by(|a, b| a.s_r[0].total_cmp(&b.s_r[0]));
    let hs = opts.step;
    // Windows (node ranges, with the candidate whose estimate guesses the wheel point at the
    // start); windows that meet or touch are one, travelled as one anchored run.
    const MAX_WINDOWS: usize = 16;
    let mut windows = [(0i64, 0i64, 0usize); MAX_WINDOWS];
    let mut n = 0;
    let mut i = 0;
    while i < cands.len() {
        let (j, end) = run_from(cands, i);
        let k0 = ((cands[i].s_r[0] / hs + 1e-9).floor() as i64 - 2).max(0);
        let k1 = (end / hs - 1e-9).ceil() as i64 + 2;
        match windows[..n].last_mut() {
            Some(w) if k0 <= w.1 + 1 => w.1 = w.1.max(k1),
            _ if n == MAX_WINDOWS => return false,
            _ => {
                windows[n] = (k0, k1, i);
                n += 1;
            }
        }
        i = j + 1;
    }
    for &(k0, k1, c) in &windows[..n] {
        let first = &cands[c];
        let guess = first.s_w_est - (first.s_r_est - k0 as f64 * hs);
        let start = out.len();
        if anchored_run(pair, ctx, opts, k0, guess, RunEnd::At(k1), out, stats).is_none() {
            return false;
        }
        // Every window must begin and end outside the wheel: a zone cut by a window's end
        // would be incomplete.
        let run = &out[start..];
        if run.first().is_none_or(|p| p.gap < 0.0) || run.last().is_none_or(|p| p.gap < 0.0) {
            return false;
        }
    }
    out.len() >= 3
}
