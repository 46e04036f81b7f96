//! Profile file readers: SIMPACK `.prw`/`.prr` and plain y-z tables in mm.

use std::path::Path;

use crate::profile::validate;
use crate::{Profile, ProfileError, ProfileKind};

fn read_text(path: &Path) -> Result<(String, String), ProfileError> {
    let name = path.display().to_string();
    match std::fs::read_to_string(path) {
        Ok(t) => Ok((t, name)),
        Err(e) => Err(ProfileError::Io {
            source_name: name,
            message: e.to_string(),
        }),
    }
}

/// Reads a SIMPACK wheel (`.prw`) or rail (`.prr`) profile; see [`parse_simpack`].
pub fn read_simpack(path: &Path, kind: ProfileKind) -> Result<Profile, ProfileError> {
    let (text, name) = read_text(path)?;
    parse_simpack(&text, &name, kind)
}

/// Reads a plain y-z table in mm; see [`parse_table_mm`].
pub fn read_table_mm(path: &Path, kind: ProfileKind) -> Result<Profile, ProfileError> {
    let (text, name) = read_text(path)?;
    parse_table_mm(&text, &name, kind)
}

/// Removes a `!` comment that is not inside single quotes.
fn strip_bang(line: &str) -> &str {
    let mut quoted = false;
    for (i, c) in line.char_indices() {
        match c {
            '\'' => quoted = !quoted,
            '!' if !quoted => return &line[..i],
            _ => {}
        }
    }
    line
}

fn number(src: &str, line: usize, what: &str, text: &str) -> Result<f64, ProfileError> {
    let t = text.trim();
    let v: f64 = t.parse().map_err(|_| ProfileError::NotANumber {
        source_name: src.into(),
        line,
        what: what.into(),
        found: t.into(),
    })?;
    if !v.is_finite() {
        return Err(ProfileError::NonFinite {
            source_name: src.into(),
            line: Some(line),
            index: 0,
            what: what.into(),
            value: v,
        });
    }
    Ok(v)
}

/// SIMPACK processing parameters of the `spline` block (file units).
#[derive(Debug)]
struct Processing {
    dist_min: f64,
    shift: [f64; 2],
    rotate: f64,
    bound_y: [f64; 2],
    bound_z: [f64; 2],
    mirror_y: bool,
    mirror_z: bool,
    inversion: bool,
    len_f: f64,
    ang_f: f64,
}

const HEADER_KEYS: &str = "version, type";
const SPLINE_KEYS: &str = "approx.smooth, file, file.mtime, comment, type, point.dist.min, \
shift.y, shift.z, rotate, bound.y.min, bound.y.max, bound.z.min, bound.z.max, mirror.y, \
mirror.z, inversion, units.len, units.ang, units.len.f, units.ang.f";

#[derive(PartialEq, Clone, Copy)]
enum Block {
    Top,
    Header,
    Spline,
    Points,
    Done,
}

/// Parses the text of a SIMPACK profile (`.prw` wheel, `.prr` rail).
///
/// Structure: `header.begin … header.end` (`version`, `type` = 0 rail / 1 wheel, which must
/// match `kind`), then `spline.begin … spline.end` with processing keys and a
/// `point.begin … point.end` block of `y z [weight]` rows. `!` starts a comment. The
/// processing follows the order of CONTACT's SIMPACK reader (contact-theory §5.4):
/// 1. drop points closer than `point.dist.min` to the last kept point;
/// 2. add `shift.y`, `shift.z`;
/// 3. rotate by `rotate` (angle units) about the origin, counter-clockwise from y toward z;
/// 4. drop points outside `[bound.y.min, bound.y.max]` (inactive if min >= max);
/// 5. clip z to `[bound.z.min, bound.z.max]` (inactive if min >= max);
/// 6. `mirror.y`: y -> -y; 7. `mirror.z`: z -> -z; 8. `inversion`: reverse the point order;
/// 9. length unit: metres = value / `units.len.f`.
///
/// The result is CONTACT's canonical form (y toward the field side, z down); it is then
/// converted to this crate's frame (y = y_c, z = -z_c, in metres) and sorted to increasing y
/// (the points must be strictly monotonic in y, in either direction). Spline weights (third
/// column) are checked but not used; `approx.smooth` is ignored, as CONTACT does.
pub fn parse_simpack(
    text: &str,
    source_name: &str,
    kind: ProfileKind,
) -> Result<Profile, ProfileError> {
    let src = source_name;
    let mut pr = Processing {
        dist_min: 0.0,
        shift: [0.0; 2],
        rotate: 0.0,
        bound_y: [1.0, 0.0],
        bound_z: [1.0, 0.0],
        mirror_y: false,
        mirror_z: false,
        inversion: false,
        len_f: 1000.0,
        ang_f: 1.0,
    };
    let mut len_f_given = false;
    let mut ang_f_given = false;
    let mut block = Block::Top;
    let mut pts: Vec<[f64; 2]> = Vec::new();
    let mut lines: Vec<usize> = Vec::new();
    let mut saw_points = false;

    for (i, raw) in text.lines().enumerate() {
        let ln = i + 1;
        let line = strip_bang(raw).trim();
        if line.is_empty() {
            continue;
        }
        let unexpected = |expected: &str| ProfileError::InvalidValue {
            source_name: src.into(),
            line: ln,
            key: "structure".into(),
            found: line.into(),
            expected: expected.into(),
        };
        match block {
            Block::Points => {
                if line == "point.end" {
                    block = Block::Spline;
                    continue;
                }
                let cols: Vec<&str> = line
                    .split(|c: char| c.is_whitespace() || c == ',' || c == ';')
                    .filter(|s| !s.is_empty())
                    .collect();
                if cols.len() < 2 || cols.len() > 3 {
                    return Err(ProfileError::InvalidValue {
                        source_name: src.into(),
                        line: ln,
                        key: "point".into(),
                        found: line.into(),
                        expected: "2 or 3 columns: y z [weight]".into(),
                    });
                }
                let y = number(src, ln, "y", cols[0])?;
                let z = number(src, ln, "z", cols[1])?;
                if cols.len() == 3 {
                    let w = number(src, ln, "weight", cols[2])?;
                    if w < 0.0 {
                        return Err(ProfileError::InvalidValue {
                            source_name: src.into(),
                            line: ln,
                            key: "weight".into(),
                            found: cols[2].into(),
                            expected: "a weight >= 0".into(),
                        });
                    }
                }
                pts.push([y, z]);
                lines.push(ln);
            }
            Block::Top | Block::Done => match line {
                "header.begin" if block == Block::Top => block = Block::Header,
                "spline.begin" if block == Block::Top => block = Block::Spline,
                _ => return Err(unexpected("'header.begin' or 'spline.begin'")),
            },
            Block::Header => {
                if line == "header.end" {
                    block = Block::Top;
                    continue;
                }
                let (key, val) = split_key(src, ln, line)?;
                match key {
                    "version" => {
                        number(src, ln, key, val)?;
                    }
                    "type" => {
                        let t = number(src, ln, key, val)?;
                        let want = match kind {
                            ProfileKind::Rail => 0.0,
                            ProfileKind::Wheel => 1.0,
                        };
                        if t != want {
                            return Err(ProfileError::InvalidValue {
                                source_name: src.into(),
                                line: ln,
                                key: "type".into(),
                                found: val.into(),
                                expected: format!(
                                    "{want} for a {kind:?} profile (0 = rail, 1 = wheel)"
                                ),
                            });
                        }
                    }
                    _ => {
                        return Err(ProfileError::UnknownKey {
                            source_name: src.into(),
                            line: ln,
                            key: key.into(),
                            block: "header".into(),
                            expected: HEADER_KEYS.into(),
                        });
                    }
                }
            }
            Block::Spline => {
                match line {
                    "point.begin" => {
                        block = Block::Points;
                        saw_points = true;
                        continue;
                    }
                    "spline.end" => {
                        block = Block::Done;
                        continue;
                    }
                    _ => {}
                }
                let (key, val) = split_key(src, ln, line)?;
                let num = || number(src, ln, key, val);
                let flag = || -> Result<bool, ProfileError> {
                    match val {
                        "0" => Ok(false),
                        "1" => Ok(true),
                        _ => Err(ProfileError::InvalidValue {
                            source_name: src.into(),
                            line: ln,
                            key: key.into(),
                            found: val.into(),
                            expected: "0 or 1".into(),
                        }),
                    }
                };
                let positive = |v: f64| {
                    if v > 0.0 {
                        Ok(v)
                    } else {
                        Err(ProfileError::InvalidValue {
                            source_name: src.into(),
                            line: ln,
                            key: key.into(),
                            found: val.into(),
                            expected: "a number > 0".into(),
                        })
                    }
                };
                match key {
                    "approx.smooth" | "file.mtime" | "type" => {
                        num()?;
                    }
                    "file" | "comment" => {}
                    "point.dist.min" => pr.dist_min = num()?,
                    "shift.y" => pr.shift[0] = num()?,
                    "shift.z" => pr.shift[1] = num()?,
                    "rotate" => pr.rotate = num()?,
                    "bound.y.min" => pr.bound_y[0] = num()?,
                    "bound.y.max" => pr.bound_y[1] = num()?,
                    "bound.z.min" => pr.bound_z[0] = num()?,
                    "bound.z.max" => pr.bound_z[1] = num()?,
                    "mirror.y" => pr.mirror_y = flag()?,
                    "mirror.z" => pr.mirror_z = flag()?,
                    "inversion" => pr.inversion = flag()?,
                    "units.len.f" => {
                        pr.len_f = positive(num()?)?;
                        len_f_given = true;
                    }
                    "units.ang.f" => {
                        pr.ang_f = positive(num()?)?;
                        ang_f_given = true;
                    }
                    "units.len" => {
                        let f = match val.trim_matches('\'').trim() {
                            "m" => 1.0,
                            "dm" => 10.0,
                            "cm" => 100.0,
                            "mm" => 1000.0,
                            _ => {
                                return Err(ProfileError::InvalidValue {
                                    source_name: src.into(),
                                    line: ln,
                                    key: key.into(),
                                    found: val.into(),
                                    expected: "'m', 'dm', 'cm' or 'mm'".into(),
                                });
                            }
                        };
                        if !len_f_given {
                            pr.len_f = f;
                        }
                    }
                    "units.ang" => {
                        let f = match val.trim_matches('\'').trim() {
                            "rad" => 1.0,
                            "deg" => 180.0 / std::f64::consts::PI,
                            _ => {
                                return Err(ProfileError::InvalidValue {
                                    source_name: src.into(),
                                    line: ln,
                                    key: key.into(),
                                    found: val.into(),
                                    expected: "'rad' or 'deg'".into(),
                                });
                            }
                        };
                        if !ang_f_given {
                            pr.ang_f = f;
                        }
                    }
                    _ => {
                        return Err(ProfileError::UnknownKey {
                            source_name: src.into(),
                            line: ln,
                            key: key.into(),
                            block: "spline".into(),
                            expected: SPLINE_KEYS.into(),
                        });
                    }
                }
            }
        }
    }
    if !saw_points {
        return Err(ProfileError::MissingPointBlock {
            source_name: src.into(),
        });
    }
    if block == Block::Points {
        return Err(ProfileError::InvalidValue {
            source_name: src.into(),
            line: text.lines().count(),
            key: "point.end".into(),
            found: "end of file".into(),
            expected: "'point.end' closing the point block".into(),
        });
    }
    let read = pts.len();
    let (pts, lines) = process(pts, lines, &pr);
    // Few points left by the file's own processing (a bound, a rotation that turns the profile
    // out of the bound, a minimum distance): say so, the points are in the file.
    if pts.len() < 4 && read >= 4 {
        return Err(ProfileError::InvalidValue {
            source_name: src.into(),
            line: text.lines().count(),
            key: "point.dist.min, rotate, bound.y".into(),
            found: format!(
                "{} of the {read} points read left after the file's processing",
                pts.len()
            ),
            expected: "at least 4 profile points (check the processing keys)".into(),
        });
    }
    // Canonical (y field, z down, file units) -> crate frame (z up, metres).
    let pts: Vec<[f64; 2]> = pts
        .iter()
        .map(|p| [p[0] / pr.len_f, -p[1] / pr.len_f])
        .collect();
    finish(src, kind, pts, lines)
}

fn split_key<'a>(src: &str, ln: usize, line: &'a str) -> Result<(&'a str, &'a str), ProfileError> {
    match line.split_once('=') {
        Some((k, v)) => Ok((k.trim(), v.trim())),
        None => Err(ProfileError::InvalidValue {
            source_name: src.into(),
            line: ln,
            key: "structure".into(),
            found: line.into(),
            expected: "'key = value' or a block keyword".into(),
        }),
    }
}

/// Applies SIMPACK processing steps 1-8 (file units); line numbers follow their points.
fn process(pts: Vec<[f64; 2]>, lines: Vec<usize>, pr: &Processing) -> (Vec<[f64; 2]>, Vec<usize>) {
    let mut out: Vec<([f64; 2], usize)> = Vec::with_capacity(pts.len());
    for (p, l) in pts.into_iter().zip(lines) {
        // 1. minimum point distance
        if pr.dist_min > 0.0
            && let Some((q, _)) = out.last()
            && ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt() < pr.dist_min
        {
            continue;
        }
        out.push((p, l));
    }
    let (s, c) = (pr.rotate / pr.ang_f).sin_cos();
    let mut res: Vec<([f64; 2], usize)> = Vec::with_capacity(out.len());
    for (p, l) in out {
        // 2. shift, 3. rotate
        let y = p[0] + pr.shift[0];
        let z = p[1] + pr.shift[1];
        let (mut y, mut z) = (c * y - s * z, s * y + c * z);
        // 4. y bounds
        if pr.bound_y[0] < pr.bound_y[1] && (y < pr.bound_y[0] || y > pr.bound_y[1]) {
            continue;
        }
        // 5. z clipping
        if pr.bound_z[0] < pr.bound_z[1] {
            z = z.clamp(pr.bound_z[0], pr.bound_z[1]);
        }
        // 6., 7. mirroring
        if pr.mirror_y {
            y = -y;
        }
        if pr.mirror_z {
            z = -z;
        }
        res.push(([y, z], l));
    }
    // 8. inversion
    if pr.inversion {
        res.reverse();
    }
    res.into_iter().unzip()
}

/// Validates points in file order (monotonic in either direction) and sorts to increasing y.
fn finish(
    src: &str,
    kind: ProfileKind,
    mut pts: Vec<[f64; 2]>,
    mut lines: Vec<usize>,
) -> Result<Profile, ProfileError> {
    let dir = if pts.len() >= 2 && pts[pts.len() - 1][0] < pts[0][0] {
        -1.0
    } else {
        1.0
    };
    validate(src, &pts, Some(&lines), dir)?;
    if dir < 0.0 {
        pts.reverse();
        lines.reverse();
    }
    Ok(Profile {
        name: src.into(),
        kind,
        points: pts,
    })
}

/// Parses a plain table of `y z` rows in mm (profile frame: y toward the field side, z up).
///
/// Columns are separated by commas, semicolons or whitespace; `#` starts a comment; the first
/// non-comment line may be a header of non-numbers (e.g. `y_mm, z_mm`). Further columns are
/// not allowed. The rows must be strictly monotonic in y (either direction; the result is
/// sorted to increasing y). Use [`Profile::mirrored_z`] for data given with z downward.
pub fn parse_table_mm(
    text: &str,
    source_name: &str,
    kind: ProfileKind,
) -> Result<Profile, ProfileError> {
    let src = source_name;
    // (a byte-order mark, as spreadsheet programs write, is not part of the first line)
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut pts = Vec::new();
    let mut lines = Vec::new();
    let mut first = true;
    for (i, raw) in text.lines().enumerate() {
        let ln = i + 1;
        let line = raw.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let cols: Vec<&str> = line
            .split(|c: char| c.is_whitespace() || c == ',' || c == ';')
            .filter(|s| !s.is_empty())
            .collect();
        let is_header = first && cols.iter().all(|c| c.parse::<f64>().is_err());
        first = false;
        if is_header {
            continue;
        }
        if cols.len() != 2 {
            return Err(ProfileError::InvalidValue {
                source_name: src.into(),
                line: ln,
                key: "row".into(),
                found: line.into(),
                expected: "2 columns: y z (mm)".into(),
            });
        }
        let y = number(src, ln, "y", cols[0])?;
        let z = number(src, ln, "z", cols[1])?;
        pts.push([y / 1000.0, z / 1000.0]);
        lines.push(ln);
    }
    finish(src, kind, pts, lines)
}
