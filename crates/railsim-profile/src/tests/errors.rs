//! Bad input produces the right error variant with the right line number.

use crate::*;

const HEAD: &str = "header.begin\n  version = 1\n  type = 1\nheader.end\nspline.begin\n  mirror.y = 0\n  units.len.f = 1000\n  point.begin\n";
// Lines 1-8 above; points start at line 9.

fn wheel(points: &str) -> Result<Profile, ProfileError> {
    let text = format!("{HEAD}{points}  point.end\nspline.end\n");
    parse_simpack(&text, "profiles/x.prw", ProfileKind::Wheel)
}

#[test]
fn good_minimal_file() {
    let p = wheel("0 0\n10 0.1\n20 0.3 1.0 ! weight\n30 0.6\n").unwrap();
    assert_eq!(p.points.len(), 4);
    assert_eq!(p.points[1], [10e-3, -0.1e-3]);
}

#[test]
fn not_a_number() {
    let e = wheel("0 0\n1 abc\n2 0\n3 0\n").unwrap_err();
    assert!(
        matches!(&e, ProfileError::NotANumber { line: 10, what, found, .. } if what == "z" && found == "abc"),
        "{e:?}"
    );
    assert_eq!(
        e.to_string(),
        "profiles/x.prw:10: expected a number for z, found \"abc\""
    );
}

#[test]
fn non_finite() {
    let e = wheel("0 0\n1 0\nnan 0\n3 0\n").unwrap_err();
    assert!(
        matches!(e, ProfileError::NonFinite { line: Some(11), .. }),
        "{e:?}"
    );
    let e = wheel("0 0\n1 0\n2 inf\n3 0\n").unwrap_err();
    assert!(
        e.to_string()
            .starts_with("profiles/x.prw:11: z is not finite"),
        "{e}"
    );
}

#[test]
fn too_few_points() {
    let e = wheel("0 0\n1 0\n2 0\n").unwrap_err();
    assert!(
        matches!(e, ProfileError::TooFewPoints { found: 3, .. }),
        "{e:?}"
    );
}

#[test]
fn repeated_and_backward_points() {
    let e = wheel("0 0\n1 0\n1 0\n3 0\n").unwrap_err();
    assert!(
        matches!(
            e,
            ProfileError::RepeatedPoint {
                line: Some(11),
                prev_line: Some(10),
                ..
            }
        ),
        "{e:?}"
    );
    assert!(e.to_string().contains("line 10"), "{e}");
    let e = wheel("0 0\n1 0\n2 0\n1.5 0.5\n4 0\n").unwrap_err();
    assert!(
        matches!(
            e,
            ProfileError::NotMonotonic {
                line: Some(12),
                prev_line: Some(11),
                ..
            }
        ),
        "{e:?}"
    );
    // In-memory points report the index.
    let e = Profile::new(
        "p",
        ProfileKind::Rail,
        vec![[0.0, 0.0], [1e-3, 0.0], [0.5e-3, 1e-3], [2e-3, 0.0]],
    )
    .unwrap_err();
    assert!(
        matches!(
            e,
            ProfileError::NotMonotonic {
                line: None,
                index: 2,
                ..
            }
        ),
        "{e:?}"
    );
    assert!(e.to_string().contains("point 3"), "{e}");
}

#[test]
fn self_intersection() {
    // The outline turns back and crosses its own first segment.
    let e = wheel("0 0\n2 0\n3 1\n1 1\n1 -1\n").unwrap_err();
    assert!(
        matches!(
            e,
            ProfileError::SelfIntersection {
                line: Some(13),
                other_line: Some(10),
                ..
            }
        ),
        "{e:?}"
    );
}

#[test]
fn simpack_keys() {
    let text = "header.begin\n  type = 0\nheader.end\n";
    let e = parse_simpack(text, "r.prr", ProfileKind::Wheel).unwrap_err();
    assert!(
        matches!(&e, ProfileError::InvalidValue { line: 2, key, .. } if key == "type"),
        "{e:?}"
    );
    let e = parse_simpack(text, "r.prr", ProfileKind::Rail).unwrap_err();
    assert!(matches!(e, ProfileError::MissingPointBlock { .. }), "{e:?}");
    let text = "spline.begin\n  shift.q = 3\n";
    let e = parse_simpack(text, "r.prr", ProfileKind::Rail).unwrap_err();
    assert!(
        matches!(&e, ProfileError::UnknownKey { line: 2, key, .. } if key == "shift.q"),
        "{e:?}"
    );
    let text = "spline.begin\n ! c\n  mirror.y = 2\n";
    let e = parse_simpack(text, "r.prr", ProfileKind::Rail).unwrap_err();
    assert!(
        matches!(&e, ProfileError::InvalidValue { line: 3, key, .. } if key == "mirror.y"),
        "{e:?}"
    );
    let text = "spline.begin\n  rotate = x1\n";
    let e = parse_simpack(text, "r.prr", ProfileKind::Rail).unwrap_err();
    assert!(
        matches!(&e, ProfileError::NotANumber { line: 2, what, .. } if what == "rotate"),
        "{e:?}"
    );
    let e = read_simpack(
        std::path::Path::new("/nonexistent/x.prr"),
        ProfileKind::Rail,
    )
    .unwrap_err();
    assert!(matches!(e, ProfileError::Io { .. }));
}

#[test]
fn simpack_processing_steps() {
    // shift, mirror.z, inversion, units (cm), bounds, point.dist.min.
    let text = "spline.begin\n shift.y = 1\n mirror.z = 1\n inversion = 1\n units.len.f = 100\n \
                bound.y.min = 0\n bound.y.max = 5.5\n point.dist.min = 0.5\n point.begin\n\
                -2 0\n-1 1\n-0.9 1\n0 2\n1 3\n2 4\n3 5\n9 9\n point.end\nspline.end\n";
    let p = parse_simpack(text, "t.prr", ProfileKind::Rail).unwrap();
    // kept: y(after shift) = 0,1,2,3,4 (y=-0.9+1 dropped by dist.min, -1 and 10 out of bounds)
    let ys: Vec<f64> = p.points.iter().map(|q| q[0]).collect();
    assert_eq!(ys, vec![0.0, 0.01, 0.02, 0.03, 0.04]);
    // mirror.z then canonical z-down -> z up: z = +z_file / 100.
    assert!((p.points[1][1] - 0.02).abs() < 1e-15);
    // rotate by 90 degrees in degrees units.
    let text = "spline.begin\n units.ang = 'deg'\n rotate = 90\n point.begin\n0 0\n0 10\n0 20\n0 30\n point.end\nspline.end\n";
    let p = parse_simpack(text, "t.prr", ProfileKind::Rail).unwrap();
    assert!(
        (p.points[0][0] + 0.03).abs() < 1e-12 && p.points[0][1].abs() < 1e-12,
        "{:?}",
        p.points
    );
}

#[test]
fn table_reader() {
    let text = "# measured\ny_mm; z_mm\n-10, 1\n0 0\n10;1 # c\n20 3\n";
    let p = parse_table_mm(text, "t.csv", ProfileKind::Rail).unwrap();
    assert_eq!(p.points.len(), 4);
    assert_eq!(p.points[0], [-0.01, 0.001]);
    let e = parse_table_mm("y z\n0 0\n1 x\n", "t.csv", ProfileKind::Rail).unwrap_err();
    assert!(
        matches!(e, ProfileError::NotANumber { line: 3, .. }),
        "{e:?}"
    );
    let e = parse_table_mm("0 0\n1 1 1\n", "t.csv", ProfileKind::Rail).unwrap_err();
    assert!(
        matches!(e, ProfileError::InvalidValue { line: 2, .. }),
        "{e:?}"
    );
    // a byte-order mark before the header is not part of it
    let bom = parse_table_mm(
        "\u{feff}y_mm z_mm\n-10 1\n0 0\n10 1\n20 3\n",
        "t.csv",
        ProfileKind::Rail,
    );
    assert_eq!(bom.unwrap().points.len(), 4);
    // Descending rows are accepted and sorted.
    let p = parse_table_mm("30 0\n20 1\n10 0\n0 1\n", "t.csv", ProfileKind::Rail).unwrap();
    assert_eq!(p.points[0][0], 0.0);
}

#[test]
fn absurd_coordinates() {
    // 1e300 mm is finite but no profile: a unit or data error, located (it used to pass the
    // reader and fail in the spline fit without a line)
    let e = wheel("0 0\n1 0\n2 1e300\n3 0\n").unwrap_err();
    assert!(
        matches!(&e, ProfileError::OutOfRange { line: Some(11), what, .. } if what == "z"),
        "{e:?}"
    );
    assert_eq!(
        e.to_string(),
        "profiles/x.prw:11: z = -1e300 mm (profile frame) is out of range, expected |z| <= 1000 mm"
    );
    // a whole rail, 172 mm high, is well within the limit
    assert!(wheel("0 0\n10 -172\n20 -172.5\n30 -100\n").is_ok());
}

/// Points read but dropped by the file's own processing keys (here a y bound that keeps two of
/// six) are reported as such, not as a file with too few points.
#[test]
fn points_left_out_by_the_processing_keys() {
    let text = HEAD.replace(
        "  point.begin\n",
        "  bound.y.min = 0\n  bound.y.max = 1.5\n  point.begin\n",
    ) + "0 0\n1 0.1\n2 0.3\n3 0.6\n4 1.0\n5 1.5\n  point.end\nspline.end\n";
    let e = parse_simpack(&text, "profiles/x.prw", ProfileKind::Wheel).unwrap_err();
    let msg = e.to_string();
    assert!(
        msg.contains("2 of the 6 points read left after the file's processing")
            && msg.contains("point.dist.min, rotate, bound.y"),
        "{msg}"
    );
    // with too few points in the file itself the message stays the plain one
    let e = wheel("0 0\n1 0.1\n").unwrap_err();
    assert!(
        matches!(e, ProfileError::TooFewPoints { found: 2, .. }),
        "{e:?}"
    );
}

/// A profile given in metres where millimetres are expected spans a fraction of a millimetre: it
/// is refused, naming the file and the span, instead of giving a plausible-looking contact.
#[test]
fn a_profile_in_metres_is_too_narrow() {
    let e = wheel("0 0\n0.01 0.0001\n0.02 0.0003\n0.03 0.0006\n").unwrap_err();
    assert!(matches!(e, ProfileError::TooNarrow { .. }), "{e:?}");
    assert_eq!(
        e.to_string(),
        "profiles/x.prw: the profile spans only 0.03 mm laterally (y from 0 to 0.03 mm), expected at least 20 mm (coordinates in metres where millimetres are expected?)"
    );
    let e = parse_table_mm("0 0\n5 1\n10 0\n15 1\n", "t.csv", ProfileKind::Rail).unwrap_err();
    assert!(matches!(e, ProfileError::TooNarrow { .. }), "{e:?}");
}
