//! The [`Profile`] type: a validated 2-D cross-section polyline.

use crate::ProfileError;

/// Whether a profile describes a wheel or a rail.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ProfileKind {
    /// Wheel profile: y = S of EN 13715, z = -F(S) (radius r0 - z).
    Wheel,
    /// Rail profile: y toward the field side, z up.
    Rail,
}

/// A 2-D cross-section in its own profile frame.
///
/// y is lateral, positive toward the field side; z is positive up; points are strictly
/// increasing in y. See the crate documentation for the wheel and rail origins.
#[derive(Clone, Debug)]
pub struct Profile {
    /// Name used in messages (usually the file name).
    pub name: String,
    /// Wheel or rail.
    pub kind: ProfileKind,
    /// \[m\] (y, z) points, y strictly increasing
    pub points: Vec<[f64; 2]>,
}

impl Profile {
    /// Builds a profile from points in metres, checking that there are at least 4 points,
    /// that all are finite, that y increases strictly (a repeated point or one that goes back
    /// is reported with its index) and that the polyline does not intersect itself.
    pub fn new(
        name: impl Into<String>,
        kind: ProfileKind,
        points: Vec<[f64; 2]>,
    ) -> Result<Self, ProfileError> {
        let name = name.into();
        validate(&name, &points, None, 1.0)?;
        Ok(Profile { name, kind, points })
    }

    /// Mirror image y -> -y (points re-sorted to increasing y), for a profile stored for the
    /// other side.
    pub fn mirrored(&self) -> Profile {
        let points = self.points.iter().rev().map(|p| [-p[0], p[1]]).collect();
        Profile {
            name: self.name.clone(),
            kind: self.kind,
            points,
        }
    }

    /// Mirror image z -> -z (order unchanged), e.g. for data given with z downward.
    pub fn mirrored_z(&self) -> Profile {
        let points = self.points.iter().map(|p| [p[0], -p[1]]).collect();
        Profile {
            name: self.name.clone(),
            kind: self.kind,
            points,
        }
    }

    /// Scales all coordinates about the origin by `factor` (finite and > 0).
    pub fn scaled(&self, factor: f64) -> Result<Profile, ProfileError> {
        if !(factor.is_finite() && factor > 0.0) {
            return Err(ProfileError::InvalidArgument {
                source_name: self.name.clone(),
                what: "scale factor".into(),
                found: format!("{factor}"),
                expected: "a finite number > 0".into(),
            });
        }
        let points = self
            .points
            .iter()
            .map(|p| [p[0] * factor, p[1] * factor])
            .collect();
        Ok(Profile {
            name: self.name.clone(),
            kind: self.kind,
            points,
        })
    }

    /// Rotates the profile by `angle_rad` \[rad\] about the point `about` \[m\]; positive is
    /// counter-clockwise in the (y, z) plane (y toward z). The result must still have strictly
    /// increasing y, which is re-checked.
    pub fn rotated(&self, angle_rad: f64, about: [f64; 2]) -> Result<Profile, ProfileError> {
        if !(angle_rad.is_finite() && about[0].is_finite() && about[1].is_finite()) {
            return Err(ProfileError::InvalidArgument {
                source_name: self.name.clone(),
                what: "rotation".into(),
                found: format!("angle {angle_rad} about {about:?}"),
                expected: "finite angle and centre".into(),
            });
        }
        let (s, c) = angle_rad.sin_cos();
        let points: Vec<[f64; 2]> = self
            .points
            .iter()
            .map(|p| {
                let dy = p[0] - about[0];
                let dz = p[1] - about[1];
                [about[0] + c * dy - s * dz, about[1] + s * dy + c * dz]
            })
            .collect();
        validate(&self.name, &points, None, 1.0)?;
        Ok(Profile {
            name: self.name.clone(),
            kind: self.kind,
            points,
        })
    }

    /// Translates the profile by (`dy`, `dz`) \[m\] (both must be finite).
    pub fn translated(&self, dy: f64, dz: f64) -> Profile {
        let points = self.points.iter().map(|p| [p[0] + dy, p[1] + dz]).collect();
        Profile {
            name: self.name.clone(),
            kind: self.kind,
            points,
        }
    }

    /// \[m\] the y range (first, last point).
    pub fn y_range(&self) -> (f64, f64) {
        (self.points[0][0], self.points[self.points.len() - 1][0])
    }

    /// \[m\] z of the polyline at `y` (linear interpolation), `None` outside the y range.
    pub fn z_at(&self, y: f64) -> Option<f64> {
        let pts = &self.points;
        let (y0, y1) = self.y_range();
        if !(y >= y0 && y <= y1) {
            return None;
        }
        let i = pts.partition_point(|p| p[0] <= y).clamp(1, pts.len() - 1);
        let (a, b) = (pts[i - 1], pts[i]);
        let t = (y - a[0]) / (b[0] - a[0]);
        Some(a[1] + t * (b[1] - a[1]))
    }

    /// \[m\] the highest point of the polyline, refined by a parabola through the highest
    /// vertex and its neighbours (exact for sampled circles to O(h^3)).
    pub fn highest_point(&self) -> [f64; 2] {
        let pts = &self.points;
        let mut k = 0;
        for (i, p) in pts.iter().enumerate() {
            if p[1] > pts[k][1] {
                k = i;
            }
        }
        if k == 0 || k == pts.len() - 1 {
            return pts[k];
        }
        let (a, b, c) = (pts[k - 1], pts[k], pts[k + 1]);
        // Parabola z(y) through three points; vertex.
        let d1 = (b[1] - a[1]) / (b[0] - a[0]);
        let d2 = (c[1] - b[1]) / (c[0] - b[0]);
        let curv = (d2 - d1) / (c[0] - a[0]);
        if curv >= 0.0 {
            return b;
        }
        // z = b + d1 (y - a) ... use Newton form: z = a + d1 (y-ya) + curv (y-ya)(y-yb)
        let yv = 0.5 * (a[0] + b[0]) - d1 / (2.0 * curv);
        if !(yv >= a[0] && yv <= c[0]) {
            return b;
        }
        let zv = a[1] + d1 * (yv - a[0]) + curv * (yv - a[0]) * (yv - b[0]);
        [yv, zv]
    }
}

/// Checks a point list: count, finiteness, strictly monotonic y in the direction `dir`
/// (+1 increasing, -1 decreasing), and no self-intersection when monotonicity fails.
/// `lines` gives the 1-based file line of each point; coordinates are in metres.
/// \[m\] largest coordinate magnitude of a profile point: wheel and rail profiles (a whole rail
/// is 172 mm high) lie well within it; a larger value is a unit or data error.
pub const MAX_COORDINATE: f64 = 1.0;
/// \[m\] narrowest lateral extent of a profile: a rail head is some 70 mm wide and a wheel's
/// tread and flange some 130 mm; a profile narrower than this is a unit error (metres read as
/// millimetres) or a fragment that cannot carry a contact.
pub const MIN_WIDTH: f64 = 0.02;

pub(crate) fn validate(
    name: &str,
    points: &[[f64; 2]],
    lines: Option<&[usize]>,
    dir: f64,
) -> Result<(), ProfileError> {
    let line = |i: usize| lines.map(|l| l[i]);
    if points.len() < 4 {
        return Err(ProfileError::TooFewPoints {
            source_name: name.into(),
            found: points.len(),
        });
    }
    for (i, p) in points.iter().enumerate() {
        for (k, what) in [(0, "y"), (1, "z")] {
            if !p[k].is_finite() {
                return Err(ProfileError::NonFinite {
                    source_name: name.into(),
                    line: line(i),
                    index: i,
                    what: what.into(),
                    value: p[k],
                });
            }
            if p[k].abs() > MAX_COORDINATE {
                return Err(ProfileError::OutOfRange {
                    source_name: name.into(),
                    line: line(i),
                    index: i,
                    what: what.into(),
                    value_mm: p[k] * 1e3,
                    limit_mm: MAX_COORDINATE * 1e3,
                });
            }
        }
    }
    for i in 1..points.len() {
        let (a, b) = (points[i - 1], points[i]);
        if dir * (b[0] - a[0]) > 0.0 {
            continue;
        }
        if a == b {
            return Err(ProfileError::RepeatedPoint {
                source_name: name.into(),
                line: line(i),
                prev_line: line(i - 1),
                index: i,
                y_mm: b[0] * 1000.0,
                z_mm: b[1] * 1000.0,
            });
        }
        if let Some((later, earlier)) = find_self_intersection(points) {
            return Err(ProfileError::SelfIntersection {
                source_name: name.into(),
                line: line(later),
                index: later,
                other_line: line(earlier),
                other_index: earlier,
            });
        }
        return Err(ProfileError::NotMonotonic {
            source_name: name.into(),
            line: line(i),
            prev_line: line(i - 1),
            index: i,
            y_mm: b[0] * 1000.0,
            prev_y_mm: a[0] * 1000.0,
        });
    }
    // (after the point-wise checks, which name a line)
    let (lo, hi) = points
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(p[0]), hi.max(p[0]))
        });
    if hi - lo < MIN_WIDTH {
        return Err(ProfileError::TooNarrow {
            source_name: name.into(),
            y_min_mm: lo * 1e3,
            y_max_mm: hi * 1e3,
            limit_mm: MIN_WIDTH * 1e3,
        });
    }
    Ok(())
}

/// Orientation of the triangle (a, b, c): > 0 counter-clockwise.
fn orient(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// Whether closed segments pq and rs intersect.
fn segments_intersect(p: [f64; 2], q: [f64; 2], r: [f64; 2], s: [f64; 2]) -> bool {
    let d1 = orient(r, s, p);
    let d2 = orient(r, s, q);
    let d3 = orient(p, q, r);
    let d4 = orient(p, q, s);
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
    {
        return true;
    }
    let on = |a: [f64; 2], b: [f64; 2], c: [f64; 2], d: f64| {
        d == 0.0
            && c[0] >= a[0].min(b[0])
            && c[0] <= a[0].max(b[0])
            && c[1] >= a[1].min(b[1])
            && c[1] <= a[1].max(b[1])
    };
    on(r, s, p, d1) || on(r, s, q, d2) || on(p, q, r, d3) || on(p, q, s, d4)
}

/// First crossing of non-adjacent segments, as (end index of the later segment, end index of
/// the earlier segment). O(n^2); only called for point lists that are not monotonic.
fn find_self_intersection(points: &[[f64; 2]]) -> Option<(usize, usize)> {
    for i in 2..points.len() {
        for j in 1..i - 1 {
            if segments_intersect(points[j - 1], points[j], points[i - 1], points[i]) {
                return Some((i, j));
            }
        }
    }
    None
}
