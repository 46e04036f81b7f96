//! Placing a rail profile in the track's side frame (contact-theory §5.3).

use crate::{Profile, ProfileError};

/// Where a rail profile's origin ended up in the side frame (see [`place_rail`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RailPlacement {
    /// \[m\] lateral position of the profile origin in the side frame
    pub y_origin: f64,
    /// \[m\] vertical position of the profile origin in the side frame
    pub z_origin: f64,
    /// \[rad\] rotation applied (counter-clockwise in the profile's (y, z) plane, i.e. the head
    /// tilted toward the track centre)
    pub rotation: f64,
}

impl RailPlacement {
    /// Maps a point \[m\] of the original (unplaced) profile frame into the side frame.
    pub fn apply(&self, p: [f64; 2]) -> [f64; 2] {
        let (s, c) = self.rotation.sin_cos();
        [
            self.y_origin + c * p[0] - s * p[1],
            self.z_origin + s * p[0] + c * p[1],
        ]
    }
}

/// Places a rail in the "side frame": y = lateral distance from the track centre line,
/// positive toward this rail's field side; z up with z = 0 at the highest point of the
/// (inclined) rail head.
///
/// The profile is rotated by `inclination_rad` \[rad\] about its origin toward the track centre
/// (counter-clockwise in (y, z): 1:40 -> atan(1/40); use 0 for a file that is already
/// inclined), its highest point is found (parabolic refinement between samples), and it is
/// shifted so that the gauge-side point `gauge_depth` \[m\] (usually 0.014) below the highest
/// point lies at y = `gauge` / 2 \[m\] (linear interpolation between samples). Flank points that
/// the rotation makes vertical or overhanging (no longer strictly increasing in y, counted
/// outward from the highest point) are dropped: with 1:20 the 1:20 gauge-side flank of UIC60
/// becomes vertical. Procedure of
/// contact-theory §5.3; for the analytic UIC60 at 1:40 and gauge 1.435 m the crown point on the
/// rail axis lands at y = 0.753040 m.
pub fn place_rail(
    rail: &Profile,
    inclination_rad: f64,
    gauge: f64,
    gauge_depth: f64,
) -> Result<(Profile, RailPlacement), ProfileError> {
    let bad = |what: &str, v: f64, expected: &str| ProfileError::InvalidArgument {
        source_name: rail.name.clone(),
        what: what.into(),
        found: v.to_string(),
        expected: expected.into(),
    };
    if !(gauge.is_finite() && gauge > 0.0) {
        return Err(bad("gauge", gauge, "a finite gauge > 0 [m]"));
    }
    if !(gauge_depth.is_finite() && gauge_depth > 0.0) {
        return Err(bad("gauge depth", gauge_depth, "a finite depth > 0 [m]"));
    }
    let rot = if inclination_rad == 0.0 {
        rail.clone()
    } else {
        rotate_trimmed(rail, inclination_rad)?
    };
    let top = rot.highest_point();
    let pts = &rot.points;
    let z_g = top[1] - gauge_depth;
    // Walk from the highest point toward the gauge side (decreasing y).
    let k_top = pts.partition_point(|p| p[0] <= top[0]).min(pts.len() - 1);
    let mut y_g = None;
    for k in (1..=k_top).rev() {
        let (a, b) = (pts[k - 1], pts[k]);
        if a[1] <= z_g && b[1] >= z_g {
            let t = if b[1] != a[1] {
                (z_g - a[1]) / (b[1] - a[1])
            } else {
                0.0
            };
            y_g = Some(a[0] + t * (b[0] - a[0]));
            break;
        }
    }
    let Some(y_g) = y_g else {
        return Err(bad(
            "gauge depth",
            gauge_depth,
            "a depth reached by the gauge side of the rail profile",
        ));
    };
    let placement = RailPlacement {
        y_origin: 0.5 * gauge - y_g,
        z_origin: -top[1],
        rotation: inclination_rad,
    };
    let placed = rot.translated(placement.y_origin, placement.z_origin);
    Ok((placed, placement))
}

/// Rotates the rail points about the origin and keeps the part around the highest point that
/// is strictly increasing in y.
fn rotate_trimmed(rail: &Profile, angle: f64) -> Result<Profile, ProfileError> {
    if !angle.is_finite() {
        return Err(ProfileError::InvalidArgument {
            source_name: rail.name.clone(),
            what: "inclination".into(),
            found: angle.to_string(),
            expected: "a finite angle [rad]".into(),
        });
    }
    let (s, c) = angle.sin_cos();
    let pts: Vec<[f64; 2]> = rail
        .points
        .iter()
        .map(|p| [c * p[0] - s * p[1], s * p[0] + c * p[1]])
        .collect();
    let mut k = 0;
    for (i, p) in pts.iter().enumerate() {
        if p[1] > pts[k][1] {
            k = i;
        }
    }
    let mut lo = k;
    while lo > 0 && pts[lo - 1][0] < pts[lo][0] {
        lo -= 1;
    }
    let mut hi = k;
    while hi + 1 < pts.len() && pts[hi + 1][0] > pts[hi][0] {
        hi += 1;
    }
    Profile::new(rail.name.clone(), rail.kind, pts[lo..=hi].to_vec())
}
