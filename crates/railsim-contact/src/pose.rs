//! Wheelset pose and velocity in the track frame, and their mirror into a wheel's side frame.
//!
//! Track frame `T`: x along the track (direction of travel), y to the left, z up, origin on the
//! track centre line in the plane of the rail tops. The wheelset frame `W` has its origin at the
//! axle centre; its orientation is `R_TW = Rx(roll) * Rz(yaw)` (yaw first, then roll about the
//! track x-axis), which is the convention of CONTACT's wheelset position (checked to 1e-8 mm
//! against its benchmark output, see `docs/conventions.md`).
//!
//! Each wheel is computed in its *side frame* `S`: the track frame for the left wheel, and the
//! track frame mirrored in y for the right wheel. In a side frame y is always positive toward
//! that wheel's field side, so one geometry code serves both wheels, and mirroring the input
//! mirrors the result exactly.

use crate::error::{ContactError, finite};

/// Which wheel of a wheelset.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Side {
    /// The wheel on the left (y > 0 in the track frame).
    Left,
    /// The wheel on the right (y < 0 in the track frame).
    Right,
}

impl Side {
    /// +1 for the left wheel, -1 for the right: the sign that maps track y to side-frame y.
    pub fn sign(self) -> f64 {
        match self {
            Side::Left => 1.0,
            Side::Right => -1.0,
        }
    }
    /// Lower-case name, for messages and files.
    pub fn name(self) -> &'static str {
        match self {
            Side::Left => "left",
            Side::Right => "right",
        }
    }
}

/// Rigid-body pose of a wheelset relative to the track frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct WheelsetPose {
    /// \[m\] lateral displacement of the axle centre, positive to the left
    pub y: f64,
    /// \[m\] vertical displacement of the axle centre from its nominal height r0, positive up
    pub z: f64,
    /// \[rad\] roll angle about the track x-axis (right-hand rule, x forward)
    pub roll: f64,
    /// \[rad\] yaw angle about the track z-axis (positive turns the nose to the left)
    pub yaw: f64,
}

/// Velocities of a wheelset relative to the track frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct WheelsetVelocity {
    /// \[m/s\] forward speed of the axle centre (rolling speed); must be positive
    pub vx: f64,
    /// \[m/s\] lateral velocity of the axle centre
    pub vy: f64,
    /// \[m/s\] vertical velocity of the axle centre
    pub vz: f64,
    /// \[rad/s\] roll rate
    pub roll_rate: f64,
    /// \[rad/s\] yaw rate
    pub yaw_rate: f64,
    /// \[rad/s\] spin about the wheelset axle; pure rolling forward is `vx / r0` (positive)
    pub spin: f64,
}

/// \[m\] the largest wheelset lateral position an evaluation accepts.
pub const MAX_LATERAL: f64 = 0.1;

impl WheelsetPose {
    /// Check for non-finite and absurd values.
    pub fn validate(&self) -> Result<(), ContactError> {
        finite("wheelset y", self.y)?;
        finite("wheelset z", self.z)?;
        finite("wheelset roll", self.roll)?;
        finite("wheelset yaw", self.yaw)?;
        if self.roll.abs() > 0.2 {
            return Err(ContactError::OutOfRange {
                what: "wheelset roll [rad]",
                value: self.roll,
                expected: "|roll| <= 0.2 rad",
            });
        }
        if self.yaw.abs() > 0.2 {
            return Err(ContactError::OutOfRange {
                what: "wheelset yaw [rad]",
                value: self.yaw,
                expected: "|yaw| <= 0.2 rad",
            });
        }
        if self.y.abs() > MAX_LATERAL {
            return Err(ContactError::OutOfRange {
                what: "wheelset y [m]",
                value: self.y,
                expected: "|y| <= 0.1 m",
            });
        }
        Ok(())
    }

    /// The rotation `R_TW = Rx(roll) Rz(yaw)` from the wheelset frame to the track frame
    /// (row-major).
    pub fn rotation(&self) -> [[f64; 3]; 3] {
        rotation(self.roll, self.yaw)
    }

    /// A track-frame vector in the wheelset frame: `R_TW^T v`.
    pub fn track_to_wheelset(&self, v: [f64; 3]) -> [f64; 3] {
        let r = self.rotation();
        [
            r[0][0] * v[0] + r[1][0] * v[1] + r[2][0] * v[2],
            r[0][1] * v[0] + r[1][1] * v[1] + r[2][1] * v[2],
            r[0][2] * v[0] + r[1][2] * v[1] + r[2][2] * v[2],
        ]
    }

    /// The pose as seen in the side frame of `side` (mirror in y for the right wheel).
    pub fn to_side(&self, side: Side) -> WheelsetPose {
        let s = side.sign();
        WheelsetPose {
            y: s * self.y,
            z: self.z,
            roll: s * self.roll,
            yaw: s * self.yaw,
        }
    }
}

impl WheelsetVelocity {
    /// Check for non-finite values and a positive rolling speed.
    pub fn validate(&self) -> Result<(), ContactError> {
        finite("wheelset vx", self.vx)?;
        finite("wheelset vy", self.vy)?;
        finite("wheelset vz", self.vz)?;
        finite("wheelset roll rate", self.roll_rate)?;
        finite("wheelset yaw rate", self.yaw_rate)?;
        finite("wheelset spin", self.spin)?;
        if self.vx <= 1e-6 {
            return Err(ContactError::OutOfRange {
                what: "wheelset forward speed vx [m/s]",
                value: self.vx,
                expected: "a positive rolling speed (creepages are divided by it)",
            });
        }
        Ok(())
    }

    /// The velocities as seen in the side frame of `side`. Under the mirror y -> -y, linear
    /// velocity flips its y component and angular velocity (a pseudo-vector) flips its x and z
    /// components, so spin is unchanged.
    pub fn to_side(&self, side: Side) -> WheelsetVelocity {
        let s = side.sign();
        WheelsetVelocity {
            vx: self.vx,
            vy: s * self.vy,
            vz: self.vz,
            roll_rate: s * self.roll_rate,
            yaw_rate: s * self.yaw_rate,
            spin: self.spin,
        }
    }
}

/// Rotation matrix `Rx(roll) * Rz(yaw)`, row-major.
pub(crate) fn rotation(roll: f64, yaw: f64) -> [[f64; 3]; 3] {
    let (sf, cf) = roll.sin_cos();
    let (sp, cp) = yaw.sin_cos();
    [
        [cp, -sp, 0.0],
        [cf * sp, cf * cp, -sf],
        [sf * sp, sf * cp, cf],
    ]
}

/// `m * v`.
#[inline]
pub(crate) fn mat_vec(m: &[[f64; 3]; 3], v: [f64; 3]) -> [f64; 3] {
    [
        m[0][0] * v[0] + m[0][1] * v[1] + m[0][2] * v[2],
        m[1][0] * v[0] + m[1][1] * v[1] + m[1][2] * v[2],
        m[2][0] * v[0] + m[2][1] * v[1] + m[2][2] * v[2],
    ]
}

/// `mᵀ * v`.
#[inline]
pub(crate) fn mat_t_vec(m: &[[f64; 3]; 3], v: [f64; 3]) -> [f64; 3] {
    [
        m[0][0] * v[0] + m[1][0] * v[1] + m[2][0] * v[2],
        m[0][1] * v[0] + m[1][1] * v[1] + m[2][1] * v[2],
        m[0][2] * v[0] + m[1][2] * v[1] + m[2][2] * v[2],
    ]
}

/// Cross product.
#[inline]
pub(crate) fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Dot product.
#[inline]
pub(crate) fn dot3(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
