//! Small fixed-size 3-D vector and matrix helpers for the multibody equations.
//!
//! Vectors are `[f64; 3]`, matrices `[[f64; 3]; 3]` stored by rows; `R · v` maps components in a
//! rotated frame to the frame it is rotated from (columns of `R` are the rotated axes).

/// A 3-vector.
pub type V3 = [f64; 3];
/// A 3×3 matrix, by rows.
pub type M3 = [[f64; 3]; 3];

/// The identity.
pub const IDENTITY: M3 = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

/// a + b
#[inline]
pub fn add(a: V3, b: V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// a − b
#[inline]
pub fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// k · a
#[inline]
pub fn scale(k: f64, a: V3) -> V3 {
    [k * a[0], k * a[1], k * a[2]]
}

/// a · b
#[inline]
pub fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// a × b
#[inline]
pub fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// R · v
#[inline]
pub fn mul(r: &M3, v: V3) -> V3 {
    [
        r[0][0] * v[0] + r[0][1] * v[1] + r[0][2] * v[2],
        r[1][0] * v[0] + r[1][1] * v[1] + r[1][2] * v[2],
        r[2][0] * v[0] + r[2][1] * v[1] + r[2][2] * v[2],
    ]
}

/// Rᵀ · v
#[inline]
pub fn mul_t(r: &M3, v: V3) -> V3 {
    [
        r[0][0] * v[0] + r[1][0] * v[1] + r[2][0] * v[2],
        r[0][1] * v[0] + r[1][1] * v[1] + r[2][1] * v[2],
        r[0][2] * v[0] + r[1][2] * v[1] + r[2][2] * v[2],
    ]
}

/// A · B
pub fn mat_mul(a: &M3, b: &M3) -> M3 {
    let mut c = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            c[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
        }
    }
    c
}

/// Aᵀ · B
pub fn mat_t_mul(a: &M3, b: &M3) -> M3 {
    let mut c = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            c[i][j] = a[0][i] * b[0][j] + a[1][i] * b[1][j] + a[2][i] * b[2][j];
        }
    }
    c
}

/// Rotation about x by `a` (right-handed).
pub fn rot_x(a: f64) -> M3 {
    let (s, c) = a.sin_cos();
    [[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]]
}

/// Rotation about y by `a`.
pub fn rot_y(a: f64) -> M3 {
    let (s, c) = a.sin_cos();
    [[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]]
}

/// Rotation about z by `a`.
pub fn rot_z(a: f64) -> M3 {
    let (s, c) = a.sin_cos();
    [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]
}

/// The orientation of a body relative to its track frame from (roll, pitch, yaw):
/// `Rx(roll) · Ry(pitch) · Rz(yaw)`, yaw first, the order of the contact crate's wheelset
/// (`docs/conventions.md`).
pub fn rotation_rpy(roll: f64, pitch: f64, yaw: f64) -> M3 {
    mat_mul(&mat_mul(&rot_x(roll), &rot_y(pitch)), &rot_z(yaw))
}

/// The small rotation vector of a rotation matrix close to the identity: the axial vector of
/// its skew part, (R − Rᵀ)/2: the rotation vector to first order, with an error of third order in
/// the angle.
pub fn small_rotation(r: &M3) -> V3 {
    [
        0.5 * (r[2][1] - r[1][2]),
        0.5 * (r[0][2] - r[2][0]),
        0.5 * (r[1][0] - r[0][1]),
    ]
}

/// Unit quaternion (x, y, z, w) of a rotation matrix (Shepperd's method, S.W. Shepperd,
/// J. Guidance and Control 1(3), 1978).
pub fn quaternion(r: &M3) -> [f64; 4] {
    let tr = r[0][0] + r[1][1] + r[2][2];
    let q = if tr > 0.0 {
        let s = 2.0 * (1.0 + tr).sqrt();
        [
            (r[2][1] - r[1][2]) / s,
            (r[0][2] - r[2][0]) / s,
            (r[1][0] - r[0][1]) / s,
            0.25 * s,
        ]
    } else if r[0][0] > r[1][1] && r[0][0] > r[2][2] {
        let s = 2.0 * (1.0 + r[0][0] - r[1][1] - r[2][2]).sqrt();
        [
            0.25 * s,
            (r[0][1] + r[1][0]) / s,
            (r[0][2] + r[2][0]) / s,
            (r[2][1] - r[1][2]) / s,
        ]
    } else if r[1][1] > r[2][2] {
        let s = 2.0 * (1.0 + r[1][1] - r[0][0] - r[2][2]).sqrt();
        [
            (r[0][1] + r[1][0]) / s,
            0.25 * s,
            (r[1][2] + r[2][1]) / s,
            (r[0][2] - r[2][0]) / s,
        ]
    } else {
        let s = 2.0 * (1.0 + r[2][2] - r[0][0] - r[1][1]).sqrt();
        [
            (r[0][2] + r[2][0]) / s,
            (r[1][2] + r[2][1]) / s,
            0.25 * s,
            (r[1][0] - r[0][1]) / s,
        ]
    };
    let n = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt();
    [q[0] / n, q[1] / n, q[2] / n, q[3] / n]
}

/// Inverse of a symmetric positive-definite 3×3 matrix (cofactors), `None` if singular.
pub fn inverse(a: &M3) -> Option<M3> {
    let c00 = a[1][1] * a[2][2] - a[1][2] * a[2][1];
    let c01 = a[1][2] * a[2][0] - a[1][0] * a[2][2];
    let c02 = a[1][0] * a[2][1] - a[1][1] * a[2][0];
    let det = a[0][0] * c00 + a[0][1] * c01 + a[0][2] * c02;
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let d = 1.0 / det;
    Some([
        [
            c00 * d,
            (a[0][2] * a[2][1] - a[0][1] * a[2][2]) * d,
            (a[0][1] * a[1][2] - a[0][2] * a[1][1]) * d,
        ],
        [
            c01 * d,
            (a[0][0] * a[2][2] - a[0][2] * a[2][0]) * d,
            (a[0][2] * a[1][0] - a[0][0] * a[1][2]) * d,
        ],
        [
            c02 * d,
            (a[0][1] * a[2][0] - a[0][0] * a[2][1]) * d,
            (a[0][0] * a[1][1] - a[0][1] * a[1][0]) * d,
        ],
    ])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotations_and_quaternion_agree() {
        let r = rotation_rpy(0.1, -0.2, 0.3);
        let q = quaternion(&r);
        // Rotate e_x with the quaternion and with the matrix.
        let v = [1.0, 0.0, 0.0];
        let (x, y, z, w) = (q[0], q[1], q[2], q[3]);
        let qv = [x, y, z];
        let t = scale(2.0, cross(qv, v));
        let rv = add(add(v, scale(w, t)), cross(qv, t));
        let mv = mul(&r, v);
        for k in 0..3 {
            assert!((rv[k] - mv[k]).abs() < 1e-14);
        }
        let back = mul_t(&r, mv);
        assert!((back[0] - 1.0).abs() < 1e-14);
    }

    #[test]
    fn inverse_and_small_rotation() {
        let a = [[3.0, 0.1, 0.2], [0.1, 2.0, 0.0], [0.2, 0.0, 1.0]];
        let ai = inverse(&a).unwrap();
        let p = mat_mul(&a, &ai);
        for i in 0..3 {
            for j in 0..3 {
                let e = if i == j { 1.0 } else { 0.0 };
                assert!((p[i][j] - e).abs() < 1e-14);
            }
        }
        // About one axis: sin of the angle, exactly.
        let w = small_rotation(&rot_z(-3e-4));
        assert!((w[2] - (-3e-4f64).sin()).abs() < 1e-18 && w[0] == 0.0);
        // Composed: roll, pitch, yaw up to products of the angles (second order, ≤ 1e-7 here).
        let w = small_rotation(&rotation_rpy(1e-4, 2e-4, -3e-4));
        assert!((w[0] - 1e-4).abs() < 1e-7 && (w[1] - 2e-4).abs() < 1e-7);
        assert!((w[2] + 3e-4).abs() < 1e-7);
        assert!(inverse(&[[0.0; 3]; 3]).is_none());
    }
}
