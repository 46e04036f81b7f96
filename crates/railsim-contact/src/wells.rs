//! Wells of an interpenetration zone, their shares and (STRIPES) memberships, for the Hertz
//! models and STRIPES (docs/models/contact.md §4.1).
//!
//! A Hertz patch describes one well: a local minimum of the gap with its depth and curvatures.
//! A zone can hold several wells joined by penetrating humps (a wide conformal tread contact, or
//! tread and flange root close together). Taking only the deepest well makes the load jump where
//! another well becomes the deeper one; taking every well in full counts the common part twice
//! and jumps where a well appears inside the zone. Each well `i` therefore carries the share
//!
//! `w_i = 1 − c_i (1 − ω_i)`, `c_i = h_i / d_i`, `ω_i = p_i / Σ_j p_j`, `p_i = d_i − h_i`,
//!
//! of its Hertz solution: `d_i` its depth, `h_i` the depth of the deeper of the two humps next
//! to it (0 where the gap between it and its neighbour becomes positive, or at the zone's end),
//! `p_i` its prominence, and the sum over the wells joined to it by penetrating humps. The share
//! is 1 for a well that stands alone (`h = 0`), tends to 1 for every well as the humps between
//! them rise to zero (the zone separates), tends to 0 for a well that merges into a hump (`p → 0`,
//! `h → d`), and is the same for two wells of equal depth whichever is called the deeper: the
//! Hertz load is continuous through all three events. Between the limits it blends, in the
//! spirit of CONTACT's combination of neighbouring regions (Vollebregt, CONTACT user guide,
//! "Identification of contact patches"; contact-theory note §2.5); the interpolation is this
//! crate's, measured against the half-space solution in docs/validation.md.

use crate::geometry::{IsoPair, Zone, interpenetrating_runs, run_around};

/// \[-\] wells with a smaller share carry no patch (their load is below 0.1 % of their Hertz
/// solution).
pub const SHARE_MIN: f64 = 1e-3;

/// \[m\] wells less prominent than this (absolute) or than `PROMINENCE_REL` times their depth are
/// merged into their neighbour: sampling and round-off ripples of a flat gap, not wells.
pub const PROMINENCE_ABS: f64 = 2e-8;
/// \[-\] relative part of the prominence threshold.
pub const PROMINENCE_REL: f64 = 1e-3;

/// Shares of the wells of one run, in order along the rail: `depth[i]` > 0 the depth of well `i`
/// (minus its gap), `hump[i]` ≥ 0 the depth of the hump between wells `i` and `i + 1` (0 where the
/// gap there is not negative), `share[i]` written. `hump` has one entry fewer than `depth`.
pub fn shares(depth: &[f64], hump: &[f64], share: &mut [f64]) {
    let n = depth.len();
    debug_assert!(hump.len() + 1 == n.max(1) && share.len() == n);
    let connect = |i: usize| {
        let left = if i > 0 { hump[i - 1] } else { 0.0 };
        let right = if i + 1 < n { hump[i] } else { 0.0 };
        left.max(right).max(0.0)
    };
    let mut start = 0;
    while start < n {
        // the group of wells joined by penetrating humps
        let mut end = start;
        while end + 1 < n && hump[end] > 0.0 {
            end += 1;
        }
        let total: f64 = (start..=end)
            .map(|i| (depth[i] - connect(i)).max(0.0))
            .sum();
        for i in start..=end {
            let d = depth[i];
            let h = connect(i).min(d);
            let c = if d > 0.0 { h / d } else { 1.0 };
            // (no prominence anywhere in the group: a flat zone, shared equally)
            let omega = if total > 0.0 {
                (d - h) / total
            } else {
                1.0 / (end + 1 - start) as f64
            };
            share[i] = (1.0 - c * (1.0 - omega)).clamp(0.0, 1.0);
        }
        start = end + 1;
    }
}

/// Drops the wells of a run whose prominence is below the threshold (`PROMINENCE_ABS`,
/// `PROMINENCE_REL`), least prominent first: each such well and the deeper of its two humps go;
/// the shallower hump (the highest gap between its neighbours) now joins them. The first `n`
/// entries of `depth` and `well` (the wells' depths and indices) and the first `n - 1` of `hump`
/// (the humps' depths) are edited in place (nothing is allocated); returns the number of wells
/// kept.
pub fn drop_ripples(
    depth: &mut [f64],
    well: &mut [usize],
    hump: &mut [f64],
    mut n: usize,
) -> usize {
    loop {
        let mut worst: Option<(usize, f64)> = None;
        for i in 0..n {
            let left = if i > 0 {
                hump[i - 1]
            } else {
                f64::NEG_INFINITY
            };
            let right = if i + 1 < n {
                hump[i]
            } else {
                f64::NEG_INFINITY
            };
            let h = left.max(right);
            if h == f64::NEG_INFINITY {
                continue;
            }
            let p = depth[i] - h;
            if p < PROMINENCE_ABS + PROMINENCE_REL * depth[i] && worst.is_none_or(|(_, q)| p < q) {
                worst = Some((i, p));
            }
        }
        let Some((i, _)) = worst else {
            return n;
        };
        // remove well i and its deeper hump: the shallower one is the highest gap between its
        // two neighbours
        let drop_hump = if i == 0 {
            0
        } else if i + 1 == n || hump[i - 1] > hump[i] {
            i - 1
        } else {
            i
        };
        depth.copy_within(i + 1..n, i);
        well.copy_within(i + 1..n, i);
        hump.copy_within(drop_hump + 1..n - 1, drop_hump);
        n -= 1;
    }
}

/// Reusable buffers of the split into wells (`split_into_wells`, `run_wells`).
#[derive(Clone, Debug, Default)]
pub struct WellScratch {
    depth: Vec<f64>,
    well: Vec<usize>,
    hump: Vec<f64>,
    share: Vec<f64>,
    owner: Vec<usize>,
    chi: Vec<f64>,
}

/// The pair of largest gap strictly between pairs `a` and `b` (`a` if they are neighbours).
fn hump_between(pairs: &[IsoPair], a: usize, b: usize) -> usize {
    (a + 1..b)
        .max_by(|&x, &y| pairs[x].gap.total_cmp(&pairs[y].gap))
        .unwrap_or(a)
}

/// The first and last pair of basin `b` of the `n` wells found by `run_wells` for the run
/// `first..=last`: cut at the humps (the largest gaps) between neighbouring wells.
fn basin(
    pairs: &[IsoPair],
    s: &WellScratch,
    n: usize,
    (first, last): (usize, usize),
    b: usize,
) -> (usize, usize) {
    let lo = if b == 0 {
        first
    } else {
        hump_between(pairs, s.well[b - 1], s.well[b]) + 1
    };
    let hi = if b + 1 == n {
        last
    } else {
        hump_between(pairs, s.well[b], s.well[b + 1])
    };
    (lo, hi)
}

/// \[rad\] contact-angle differences below which two wells of one run are coupled fully...
pub const COUPLED_ANGLE: f64 = 0.05;
/// \[rad\] ... and above which not at all (STRIPES, `run_wells` with `coupling`).
pub const DECOUPLED_ANGLE: f64 = 0.15;

/// \[-\] How strongly two neighbouring wells whose peaks' contact angles differ by `dangle`
/// \[rad\] act as one patch: 1 up to [`COUPLED_ANGLE`], 0 from [`DECOUPLED_ANGLE`] on, a C1
/// smoothstep between.
pub fn coupling(dangle: f64) -> f64 {
    let t = ((dangle.abs() - COUPLED_ANGLE) / (DECOUPLED_ANGLE - COUPLED_ANGLE)).clamp(0.0, 1.0);
    1.0 - t * t * (3.0 - 2.0 * t)
}

/// The wells of the interpenetrating run `first..=last` of `pairs` into `s`: their depths, peak
/// pairs and the depths of the humps between them (ripples dropped, `drop_ripples`); returns
/// their number. With `coupled` (STRIPES), each hump is raised toward the shallower of its two
/// wells by their [`coupling`]: `h' = h + k (min(d_a, d_b) - h)`. Two wells of nearly the same
/// contact angle (a wide tread zone) then act as one patch, as the elastic half-space makes them
/// (the deeper well's deformation lifts the shallower one's surface; docs/validation.md §1),
/// while a flange-root and a flange well, whose normals differ by half a radian, stay separate
/// wells that share the load (docs/models/contact.md §4.1).
pub(crate) fn run_wells(
    pairs: &[IsoPair],
    first: usize,
    last: usize,
    coupled: bool,
    s: &mut WellScratch,
) -> usize {
    s.depth.clear();
    s.well.clear();
    s.hump.clear();
    for j in first..=last {
        let left = j == first || pairs[j].gap <= pairs[j - 1].gap;
        let right = j == last || pairs[j].gap < pairs[j + 1].gap;
        if !(left && right) {
            continue;
        }
        if let Some(&a) = s.well.last() {
            s.hump
                .push((-pairs[hump_between(pairs, a, j)].gap).max(0.0));
        }
        s.depth.push(-pairs[j].gap);
        s.well.push(j);
    }
    let found = s.well.len();
    let n = drop_ripples(&mut s.depth, &mut s.well, &mut s.hump, found);
    if coupled {
        let angle = |i: usize| pairs[i].n[0].atan2(pairs[i].n[1]);
        for k in 0..n.saturating_sub(1) {
            let k_c = coupling(angle(s.well[k]) - angle(s.well[k + 1]));
            let top = s.depth[k].min(s.depth[k + 1]);
            s.hump[k] += k_c * (top - s.hump[k]).max(0.0);
        }
    }
    n
}

/// The patch zones of travelled `pairs`: every maximal run of interpenetrating pairs is cut at
/// the humps between its wells (the sampled local minima of the gap, ripples dropped), each well a
/// zone with its share; wells with a share below [`SHARE_MIN`] carry none. Replaces `zones`.
///
/// Without `coupled` (the Hertz models) the zone of a well is its basin (between the humps next
/// to it) and the wells' shares use the humps' depths. With `coupled` (STRIPES) the humps are
/// raised by the wells' coupling (`run_wells`), and the basin of a well without a patch joins
/// its neighbour across the higher hump, so that a run whose wells are all coupled is one zone,
/// as before wells were used for STRIPES.
pub(crate) fn split_into_wells(
    pairs: &[IsoPair],
    zones: &mut Vec<Zone>,
    s: &mut WellScratch,
    coupled: bool,
) {
    zones.clear();
    for (first, last) in interpenetrating_runs(pairs) {
        let n = run_wells(pairs, first, last, coupled, s);
        s.share.clear();
        s.share.resize(n, 0.0);
        shares(&s.depth[..n], &s.hump[..n.saturating_sub(1)], &mut s.share);
        // the owner of each well's basin: itself, or (coupled) the patch it joins
        s.owner.clear();
        s.owner.extend(0..n);
        if coupled {
            for k in 0..n {
                if s.share[k] >= SHARE_MIN {
                    continue;
                }
                // walk across the higher hump until a well with a patch
                let mut j = k;
                let mut guard = n;
                while s.share[j] < SHARE_MIN && guard > 0 {
                    let left = if j > 0 {
                        s.hump[j - 1]
                    } else {
                        f64::NEG_INFINITY
                    };
                    let right = if j + 1 < n {
                        s.hump[j]
                    } else {
                        f64::NEG_INFINITY
                    };
                    j = if left >= right && j > 0 {
                        j - 1
                    } else if j + 1 < n {
                        j + 1
                    } else {
                        break;
                    };
                    guard -= 1;
                }
                s.owner[k] = j;
            }
        }
        for k in 0..n {
            if s.share[k] < SHARE_MIN {
                continue;
            }
            // the basins this well owns, cut at the humps between the wells kept
            let lo = (0..n).find(|&b| s.owner[b] == k).unwrap_or(k);
            let hi = (0..n).rev().find(|&b| s.owner[b] == k).unwrap_or(k);
            zones.push(Zone {
                first: basin(pairs, s, n, (first, last), lo).0,
                last: basin(pairs, s, n, (first, last), hi).1,
                deepest: s.well[k],
                share: s.share[k],
            });
        }
    }
}

/// STRIPES: each pair's membership `chi_i = min(1, H_i / d_i)` in the well whose peak is pair
/// `peak`, returned for the pairs `lo..lo + count` (`[i - lo]`): `d_i` the pair's
/// interpenetration, `H_i` the lowest (coupled, `run_wells`) hump between the pair's basin and
/// the well's; 1 in the well's own basin, and beyond an end of the run that of the basin at that
/// end. A lone well is solved whole;
/// wells separated by a positive gap do not overlap; a well that merges into its hump (or is born
/// from a shoulder) is already counted in full by its neighbour's solution; the weights vary
/// continuously with the pose (docs/models/contact.md §4.1).
pub(crate) fn memberships<'s>(
    pairs: &[IsoPair],
    peak: usize,
    lo: usize,
    count: usize,
    s: &'s mut WellScratch,
) -> &'s [f64] {
    s.chi.clear();
    s.chi.resize(count, 1.0);
    if count == 0 || pairs[peak].gap >= 0.0 {
        return &s.chi;
    }
    let (first, last) = run_around(pairs, peak, peak);
    let n = run_wells(pairs, first, last, true, s);
    let Some(own) = s.well[..n].iter().position(|&w| w == peak) else {
        return &s.chi;
    };
    let hi = lo + count - 1;
    // a pair of basin b counts in full below the lowest hump between b and the well, in
    // proportion above it
    let fill = |s: &mut WellScratch, b: usize, h: f64| {
        let (b_first, b_last) = basin(pairs, s, n, (first, last), b);
        for i in b_first.max(lo)..=b_last.min(hi) {
            let d = -pairs[i].gap;
            s.chi[i - lo] = if d <= h { 1.0 } else { h / d };
        }
    };
    let mut h = f64::INFINITY;
    for b in (0..own).rev() {
        h = h.min(s.hump[b]);
        fill(s, b, h);
    }
    let mut h = f64::INFINITY;
    for b in own + 1..n {
        h = h.min(s.hump[b - 1]);
        fill(s, b, h);
    }
    // Pairs outside the run (the strips' neighbours at its ends) belong with the basin at that
    // end. With 1 there, the half segment next to the far end of another well's basin counted
    // in full in this well's patch: a shallow tread well joined to a deep flange-root well by
    // one touching pair took 6.4 kN of the deep well's load, lost when the pair separated.
    let below = first.saturating_sub(lo).min(count);
    if below > 0 && below < count {
        let end = s.chi[below];
        s.chi[..below].fill(end);
    }
    let above = (last + 1).saturating_sub(lo);
    if above > 0 && above < count {
        let end = s.chi[above - 1];
        s.chi[above..].fill(end);
    }
    &s.chi
}

#[cfg(test)]
mod tests {
    use super::*;

    fn share_of(depth: &[f64], hump: &[f64]) -> Vec<f64> {
        let mut s = vec![0.0; depth.len()];
        shares(depth, hump, &mut s);
        s
    }

    #[test]
    fn limits_of_the_shares() {
        // alone, or separated by a positive gap: full
        assert_eq!(share_of(&[5e-5], &[]), vec![1.0]);
        assert_eq!(share_of(&[5e-5, 3e-5], &[0.0]), vec![1.0, 1.0]);
        // humps rising to zero: both tend to 1
        let s = share_of(&[5e-5, 3e-5], &[1e-9]);
        assert!(s.iter().all(|&w| w > 0.9999), "{s:?}");
        // a well merging into its hump: its share tends to 0, the other's to 1
        let s = share_of(&[5e-5, 3e-5], &[3e-5 - 1e-12]);
        assert!(s[1] < 1e-6 && s[0] > 1.0 - 1e-6, "{s:?}");
        // equal depths: equal shares, whichever order
        let s = share_of(&[4e-5, 4e-5], &[3.5e-5]);
        assert!(
            (s[0] - s[1]).abs() < 1e-15 && s[0] > 0.5 && s[0] < 1.0,
            "{s:?}"
        );
        // the flat zone of docs/models/contact.md §8
        let s = share_of(&[75.06e-6, 74.92e-6], &[70.62e-6]);
        assert!(
            (s[0] - 0.537).abs() < 2e-3 && (s[1] - 0.521).abs() < 2e-3,
            "{s:?}"
        );
    }

    /// The shares change continuously as the depths cross and as a well appears: small
    /// changes of the inputs give small changes of the shares.
    #[test]
    fn shares_are_continuous() {
        let mut worst: f64 = 0.0;
        for k in 0..=2000 {
            // the second well deepens through the first; the hump between them stays
            let d2 = 40e-6 + 20e-6 * k as f64 / 2000.0;
            let s = share_of(&[50e-6, d2, 20e-6], &[38e-6, 10e-6]);
            let t = share_of(&[50e-6, d2 + 1e-11, 20e-6], &[38e-6, 10e-6]);
            for (a, b) in s.iter().zip(&t) {
                worst = worst.max((a - b).abs());
            }
        }
        assert!(worst < 1e-5, "{worst}");
    }

    #[test]
    fn ripples_are_dropped() {
        // an interior ripple: it goes with its deeper hump
        let mut depth = [60e-6, 50e-6 + 1e-9, 55e-6];
        let mut hump = [50e-6, 30e-6];
        let mut index = [1, 5, 9];
        assert_eq!(drop_ripples(&mut depth, &mut index, &mut hump, 3), 2);
        assert_eq!((&index[..2], &hump[..1]), (&[1, 9][..], &[30e-6][..]));
        // a flat bottom with two ripples of 1e-9 m and one real well
        let mut depth = [75e-6, 75e-6 + 1e-9, 74e-6];
        let mut hump = [75e-6 - 1e-10, 70e-6];
        let mut index = [3, 7, 20];
        assert_eq!(drop_ripples(&mut depth, &mut index, &mut hump, 3), 2);
        assert_eq!((&index[..2], &hump[..1]), (&[7, 20][..], &[70e-6][..]));
    }
}
