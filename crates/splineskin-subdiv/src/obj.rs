//! Reading and writing cages as Wavefront OBJ with OpenSubdiv's subdivision tags.
//!
//! # What is read
//!
//! | statement | meaning |
//! |---|---|
//! | `v x y z [w]` | a vertex; `w ≠ 0` divides the coordinates; `v x y z r g b` (vertex colours) is accepted and the colour dropped |
//! | `f a b c …` | a face, 1-based vertex indices (negative: relative to the last `v`); only the first number of `a/b/c` is used |
//! | `t crease nI/nF/0 …` | crease tags: `nI` even, vertex pairs; one float for all pairs or one per pair |
//! | `t corner nI/nF/0 …` | corner tags: vertices; one float for all or one per vertex |
//! | `t hole nI/0/0 …` | hole faces |
//! | other `t NAME nI/nF/nS …` | kept as [`OtherTag`] (options such as `interpolateboundary`, hierarchical edits), not applied |
//! | `vt`, `vn`, `vp`, `g`, `o`, `s`, `usemtl`, `mtllib`, comments | ignored (texture and shading data does not change the surface) |
//!
//! Tag indices are 0-based, face indices 1-based (the syntax of OpenSubdiv's regression shapes,
//! `../shared/data/subdiv/shapes/README.md`). Vertex `i` of the [`Cage`] is the `i`-th `v`
//! line, face `j` the `j`-th `f` line; vertices used by no face are kept. Anything else —
//! polylines (`l`), points (`p`), free-form geometry, unknown statements, malformed numbers or
//! tags, out-of-range indices, non-finite coordinates, and what [`Cage::new`] refuses — is an
//! [`ObjError`] naming the file, the line and what was expected.
//!
//! # Why not `tobj`
//!
//! STACK.md suggests `tobj`. It was tried and not used: it drops vertices used by no face
//! (OpenSubdiv keeps them: `catmark_nonman_bareverts`), renumbers vertices by first use (per
//! object), merges `v/vt` pairs into new vertices when asked for one index per corner (which
//! splits the topology along texture seams), reports errors without line numbers, and does not
//! read `t` tags — so a line scanner of our own would have been needed anyway for tags, bare
//! vertices and error lines. The subset of OBJ a cage needs is small enough to read here.
//!
//! ```
//! use splineskin_subdiv::{parse_obj, to_obj_string};
//!
//! let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\nt crease 2/1/0 0 1 2.5\n";
//! let cage = parse_obj(text, "square.obj")?;
//! assert_eq!(cage.face(0), &[0, 1, 2, 3]);
//! assert_eq!(cage.tags().creases[0].sharpness, 2.5);
//! // Writing and reading back gives the same cage.
//! assert_eq!(parse_obj(&to_obj_string(&cage), "again.obj")?, cage);
//! # Ok::<(), splineskin_subdiv::ObjError>(())
//! ```

use std::fmt::Write as _;
use std::path::Path;

use super::cage::{Cage, CageError, CornerTag, CreaseTag, OtherTag, Point3, SubdivTags};

/// The largest OBJ file read, in bytes (256 MiB): a cage beyond that is not an interactive
/// cage, and the limit keeps a wrong path (a device, a huge log) from exhausting memory.
pub const MAX_OBJ_BYTES: u64 = 256 << 20;

/// Errors of OBJ import and export. Every variant names the file (`file` is the name given to
/// [`parse_obj`] for text that did not come from a file) and, where there is one, the 1-based
/// line.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ObjError {
    /// The file could not be read.
    #[error("{file}: cannot read the file: {source}")]
    Read {
        /// The file.
        file: String,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// The file is larger than [`MAX_OBJ_BYTES`].
    #[error("{file}: {size} bytes is more than the limit of {limit} bytes")]
    TooLarge {
        /// The file.
        file: String,
        /// Its size.
        size: u64,
        /// The limit.
        limit: u64,
    },
    /// The file is not UTF-8 text.
    #[error("{file}: not UTF-8 text; expected an OBJ file")]
    NotText {
        /// The file.
        file: String,
    },
    /// A line could not be read.
    #[error("{file}:{line}: {what}; expected {expected}")]
    Syntax {
        /// The file.
        file: String,
        /// The 1-based line.
        line: usize,
        /// What was found.
        what: String,
        /// What was expected.
        expected: String,
    },
    /// The file has no face (so it is no OBJ cage, or an empty one).
    #[error("{file}: no `f` line; expected an OBJ file with at least one polygon")]
    NoFaces {
        /// The file.
        file: String,
    },
    /// The data read is not a valid cage; `line` is the line of the offending `v`, `f` or `t`
    /// statement.
    #[error("{file}:{line}: {source}")]
    Cage {
        /// The file.
        file: String,
        /// The 1-based line.
        line: usize,
        /// What is wrong.
        #[source]
        source: CageError,
    },
    /// The file could not be written.
    #[error("{file}: cannot write the file: {source}")]
    Write {
        /// The file.
        file: String,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
}

/// Reads the cage in the OBJ file `path` (see the [module documentation](crate::obj) for the
/// dialect).
///
/// ```no_run
/// let cage = splineskin_subdiv::read_obj("shape.obj".as_ref())?;
/// println!("{} vertices, {} faces", cage.n_vertices(), cage.n_faces());
/// # Ok::<(), splineskin_subdiv::ObjError>(())
/// ```
pub fn read_obj(path: &Path) -> Result<Cage, ObjError> {
    let file = path.display().to_string();
    let read = |source| ObjError::Read {
        file: file.clone(),
        source,
    };
    let size = std::fs::metadata(path).map_err(read)?.len();
    if size > MAX_OBJ_BYTES {
        return Err(ObjError::TooLarge {
            file,
            size,
            limit: MAX_OBJ_BYTES,
        });
    }
    let bytes = std::fs::read(path).map_err(read)?;
    let text = String::from_utf8(bytes).map_err(|_| ObjError::NotText { file: file.clone() })?;
    parse_obj(&text, &file)
}

/// Reads a cage from OBJ text; `file` names it in errors.
pub fn parse_obj(text: &str, file: &str) -> Result<Cage, ObjError> {
    let mut reader = ObjReader::default();
    for (number, raw) in text.lines().enumerate() {
        let line = number + 1;
        let content = raw.split('#').next().unwrap_or("");
        let mut words = content.split_whitespace();
        let Some(keyword) = words.next() else {
            continue;
        };
        let syntax = |what: String, expected: &str| ObjError::Syntax {
            file: file.to_owned(),
            line,
            what,
            expected: expected.to_owned(),
        };
        match keyword {
            "v" => reader.vertex(words, line, &syntax)?,
            "f" => reader.face(words, line, &syntax)?,
            "t" => reader.tag(words, line, &syntax)?,
            "vt" | "vn" | "vp" | "g" | "o" | "s" | "usemtl" | "mtllib" => {}
            "l" | "p" => {
                return Err(syntax(
                    format!("a `{keyword}` statement (polyline or point)"),
                    "polygons (`f`) only: a subdivision cage has no lines or points",
                ))
            }
            other => {
                return Err(syntax(
                    format!("unknown or unsupported statement `{other}`"),
                    "v, f, t, or the ignored vt, vn, vp, g, o, s, usemtl, mtllib",
                ))
            }
        }
    }
    reader.finish(file)
}

/// An error at the current line: what was found, and what was expected.
type Syntax<'s> = dyn Fn(String, &str) -> ObjError + 's;

/// What an OBJ file has said so far, with the line of each statement (to name it in errors).
#[derive(Default)]
struct ObjReader {
    positions: Vec<Point3>,
    position_lines: Vec<usize>,
    faces: Vec<Vec<u32>>,
    face_lines: Vec<usize>,
    tags: SubdivTags,
    // (kind, index in its list) -> line, to name the line of a tag the cage refuses.
    crease_lines: Vec<usize>,
    corner_lines: Vec<usize>,
    hole_lines: Vec<usize>,
    /// Positive face indices, checked once all vertices are known: (face, index).
    face_index_checks: Vec<(usize, i64)>,
}

impl ObjReader {
    /// `v x y z [w]` (or `v x y z r g b`).
    fn vertex<'a>(
        &mut self,
        words: impl Iterator<Item = &'a str>,
        line: usize,
        syntax: &Syntax,
    ) -> Result<(), ObjError> {
        let numbers = words
            .map(|w| {
                w.parse::<f64>()
                    .map_err(|_| syntax(format!("`{w}` is not a number"), "`v x y z [w]`"))
            })
            .collect::<Result<Vec<f64>, _>>()?;
        let p = match numbers.len() {
            3 | 6 => [numbers[0], numbers[1], numbers[2]],
            4 if numbers[3] != 0.0 => {
                let w = numbers[3];
                [numbers[0] / w, numbers[1] / w, numbers[2] / w]
            }
            4 => return Err(syntax("w = 0".into(), "a non-zero w")),
            n => {
                return Err(syntax(
                    format!("{n} numbers after `v`"),
                    "`v x y z`, `v x y z w` or `v x y z r g b`",
                ))
            }
        };
        if let Some(c) = p.iter().find(|c| !c.is_finite()) {
            return Err(syntax(
                format!("coordinate {c}"),
                "finite coordinates (no nan or inf)",
            ));
        }
        self.positions.push(p);
        self.position_lines.push(line);
        Ok(())
    }

    /// `f a b c …` with 1-based (or negative, relative) vertex references.
    fn face<'a>(
        &mut self,
        words: impl Iterator<Item = &'a str>,
        line: usize,
        syntax: &Syntax,
    ) -> Result<(), ObjError> {
        let mut face = Vec::new();
        for w in words {
            let first = w.split('/').next().unwrap_or("");
            let index: i64 = first.parse().map_err(|_| {
                syntax(
                    format!("`{w}` is not a vertex reference"),
                    "`f a b c …` with 1-based vertex indices (`a`, `a/t`, `a//n`, `a/t/n`)",
                )
            })?;
            let resolved = match index {
                0 => {
                    return Err(syntax(
                        "vertex index 0".into(),
                        "1-based indices (or negative ones relative to the last `v`)",
                    ))
                }
                i if i > 0 => {
                    self.face_index_checks.push((self.faces.len(), i));
                    i - 1
                }
                i => {
                    let n = self.positions.len();
                    let r = n as i64 + i;
                    if r < 0 {
                        return Err(syntax(
                            format!("relative vertex index {i} before the first vertex"),
                            format!("a relative index in -1..=-{n} ({n} vertices so far)").as_str(),
                        ));
                    }
                    r
                }
            };
            let resolved = u32::try_from(resolved)
                .map_err(|_| syntax(format!("vertex index {index}"), "an index below 2^32"))?;
            face.push(resolved);
        }
        self.faces.push(face);
        self.face_lines.push(line);
        Ok(())
    }

    /// `t NAME …`: creases, corners and holes kept for the cage, other tags as they are.
    fn tag<'a>(
        &mut self,
        words: impl Iterator<Item = &'a str>,
        line: usize,
        syntax: &Syntax,
    ) -> Result<(), ObjError> {
        let tag = parse_tag(words).map_err(|(what, expected)| syntax(what, &expected))?;
        match tag.name.as_str() {
            "crease" => {
                for c in crease_tags(&tag).map_err(|(w, e)| syntax(w, &e))? {
                    self.tags.creases.push(c);
                    self.crease_lines.push(line);
                }
            }
            "corner" => {
                for c in corner_tags(&tag).map_err(|(w, e)| syntax(w, &e))? {
                    self.tags.corners.push(c);
                    self.corner_lines.push(line);
                }
            }
            "hole" => {
                if !tag.floats.is_empty() || !tag.strings.is_empty() {
                    return Err(syntax(
                        "float or string arguments".into(),
                        "`t hole n/0/0 f1 … fn`",
                    ));
                }
                for &f in &tag.ints {
                    let f = u32::try_from(f)
                        .map_err(|_| syntax(format!("face {f}"), "0-based face indices ≥ 0"))?;
                    self.tags.holes.push(f);
                    self.hole_lines.push(line);
                }
            }
            _ => self.tags.other.push(tag),
        }
        Ok(())
    }

    /// The cage of what was read: at least one face, every index in range; the cage's own
    /// refusals named by the line of the statement concerned.
    fn finish(self, file: &str) -> Result<Cage, ObjError> {
        if self.faces.is_empty() {
            return Err(ObjError::NoFaces {
                file: file.to_owned(),
            });
        }
        let n = self.positions.len();
        for &(face, index) in &self.face_index_checks {
            if index as usize > n {
                return Err(ObjError::Syntax {
                    file: file.to_owned(),
                    line: self.face_lines[face],
                    what: format!("vertex index {index}"),
                    expected: format!("an index in 1..={n} (the number of `v` lines)"),
                });
            }
        }
        let ObjReader {
            positions,
            position_lines,
            faces,
            face_lines,
            tags,
            crease_lines,
            corner_lines,
            hole_lines,
            ..
        } = self;
        Cage::new(positions, faces, tags).map_err(|source| {
            let line = match &source {
                CageError::NonFiniteCoordinate { vertex, .. } => position_lines[*vertex],
                CageError::FaceTooSmall { face, .. }
                | CageError::VertexOutOfRange { face, .. }
                | CageError::RepeatedVertex { face, .. } => face_lines[*face],
                CageError::BadTag { tag, index, .. } => match *tag {
                    "crease" => crease_lines[*index],
                    "corner" => corner_lines[*index],
                    _ => hole_lines[*index],
                },
                _ => 0,
            };
            ObjError::Cage {
                file: file.to_owned(),
                line,
                source,
            }
        })
    }
}

/// Parses the words after `t`: `NAME nI/nF/nS <ints> <floats> <strings>`.
fn parse_tag<'a>(mut words: impl Iterator<Item = &'a str>) -> Result<OtherTag, (String, String)> {
    const FORM: &str = "`t NAME nI/nF/nS` followed by nI integers, nF floats and nS strings";
    let name = words
        .next()
        .ok_or_else(|| ("a `t` line without a name".to_owned(), FORM.to_owned()))?
        .to_owned();
    let counts = words.next().ok_or_else(|| {
        (
            format!("tag `{name}` without argument counts"),
            FORM.to_owned(),
        )
    })?;
    let counts: Vec<usize> = counts
        .split('/')
        .map(|c| c.parse::<usize>())
        .collect::<Result<_, _>>()
        .ok()
        .filter(|c: &Vec<usize>| c.len() == 3)
        .ok_or_else(|| (format!("tag `{name}` counts `{counts}`"), FORM.to_owned()))?;
    let rest: Vec<&str> = words.collect();
    if rest.len() != counts[0] + counts[1] + counts[2] {
        return Err((
            format!(
                "tag `{name}` with {} arguments after `{}/{}/{}`",
                rest.len(),
                counts[0],
                counts[1],
                counts[2]
            ),
            format!("exactly {} arguments", counts[0] + counts[1] + counts[2]),
        ));
    }
    let ints = rest[..counts[0]]
        .iter()
        .map(|w| {
            w.parse::<i64>().map_err(|_| {
                (
                    format!("tag `{name}`: `{w}` is not an integer"),
                    FORM.to_owned(),
                )
            })
        })
        .collect::<Result<Vec<_>, _>>()?;
    let floats = rest[counts[0]..counts[0] + counts[1]]
        .iter()
        .map(|w| {
            w.parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| {
                    (
                        format!("tag `{name}`: `{w}` is not a finite number"),
                        FORM.to_owned(),
                    )
                })
        })
        .collect::<Result<Vec<_>, _>>()?;
    let strings = rest[counts[0] + counts[1]..]
        .iter()
        .map(|s| s.to_string())
        .collect();
    Ok(OtherTag {
        name,
        ints,
        floats,
        strings,
    })
}

/// The per-element sharpness of a crease or corner tag: one float for all elements, or one per
/// element.
fn sharpness_per_element(
    tag: &OtherTag,
    n: usize,
    form: &str,
) -> Result<Vec<f64>, (String, String)> {
    if !tag.strings.is_empty() {
        return Err((
            format!("`{}` tag with string arguments", tag.name),
            form.to_owned(),
        ));
    }
    match tag.floats.len() {
        1 => Ok(vec![tag.floats[0]; n]),
        m if m == n => Ok(tag.floats.clone()),
        m => Err((
            format!(
                "`{}` tag with {n} elements and {m} sharpness values",
                tag.name
            ),
            form.to_owned(),
        )),
    }
}

fn vertex_index(tag: &OtherTag, i: i64, form: &str) -> Result<u32, (String, String)> {
    u32::try_from(i).map_err(|_| (format!("`{}` tag vertex {i}", tag.name), form.to_owned()))
}

fn crease_tags(tag: &OtherTag) -> Result<Vec<CreaseTag>, (String, String)> {
    const FORM: &str =
        "`t crease 2k/1/0` or `2k/k/0`: k vertex pairs (0-based), then the sharpness";
    if tag.ints.is_empty() || tag.ints.len() % 2 != 0 {
        return Err((
            format!("a crease tag with {} vertices", tag.ints.len()),
            FORM.to_owned(),
        ));
    }
    let n = tag.ints.len() / 2;
    let sharpness = sharpness_per_element(tag, n, FORM)?;
    (0..n)
        .map(|k| {
            Ok(CreaseTag {
                vertices: [
                    vertex_index(tag, tag.ints[2 * k], FORM)?,
                    vertex_index(tag, tag.ints[2 * k + 1], FORM)?,
                ],
                sharpness: sharpness[k],
            })
        })
        .collect()
}

fn corner_tags(tag: &OtherTag) -> Result<Vec<CornerTag>, (String, String)> {
    const FORM: &str = "`t corner k/1/0` or `k/k/0`: k vertices (0-based), then the sharpness";
    if tag.ints.is_empty() {
        return Err(("a corner tag without vertices".into(), FORM.to_owned()));
    }
    let sharpness = sharpness_per_element(tag, tag.ints.len(), FORM)?;
    tag.ints
        .iter()
        .zip(sharpness)
        .map(|(&v, sharpness)| {
            Ok(CornerTag {
                vertex: vertex_index(tag, v, FORM)?,
                sharpness,
            })
        })
        .collect()
}

/// The OBJ text of a cage: one `v` line per vertex, one `f` line per face (1-based), one
/// `t crease 2/1/0`, `t corner 1/1/0` line per tag, one `t hole` line with all holes, and the
/// kept [`OtherTag`]s. Numbers are written with Rust's shortest round-trip formatting, so
/// [`parse_obj`] reads back exactly the same cage.
pub fn to_obj_string(cage: &Cage) -> String {
    let mut s = String::new();
    // `write!` to a String cannot fail.
    for p in cage.positions() {
        let _ = writeln!(s, "v {:?} {:?} {:?}", p[0], p[1], p[2]);
    }
    for face in cage.faces() {
        s.push('f');
        for &v in face {
            let _ = write!(s, " {}", v + 1);
        }
        s.push('\n');
    }
    let tags = cage.tags();
    for c in &tags.creases {
        let _ = writeln!(
            s,
            "t crease 2/1/0 {} {} {:?}",
            c.vertices[0], c.vertices[1], c.sharpness
        );
    }
    for c in &tags.corners {
        let _ = writeln!(s, "t corner 1/1/0 {} {:?}", c.vertex, c.sharpness);
    }
    if !tags.holes.is_empty() {
        let _ = write!(s, "t hole {}/0/0", tags.holes.len());
        for f in &tags.holes {
            let _ = write!(s, " {f}");
        }
        s.push('\n');
    }
    for t in &tags.other {
        let _ = write!(
            s,
            "t {} {}/{}/{}",
            t.name,
            t.ints.len(),
            t.floats.len(),
            t.strings.len()
        );
        for i in &t.ints {
            let _ = write!(s, " {i}");
        }
        for x in &t.floats {
            let _ = write!(s, " {x:?}");
        }
        for w in &t.strings {
            let _ = write!(s, " {w}");
        }
        s.push('\n');
    }
    s
}

/// Writes `cage` to `path` as OBJ ([`to_obj_string`]) through a temporary file in the same
/// folder and a rename, so that no half-written file is left behind on failure.
///
/// ```
/// use splineskin_subdiv::{parse_obj, read_obj, write_obj};
///
/// let cage = parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "tri.obj")?;
/// let path = std::env::temp_dir().join(format!("splineskin-doc-{}.obj", std::process::id()));
/// write_obj(&cage, &path)?;
/// assert_eq!(read_obj(&path)?, cage);
/// # std::fs::remove_file(&path).unwrap();
/// # Ok::<(), splineskin_subdiv::ObjError>(())
/// ```
pub fn write_obj(cage: &Cage, path: &Path) -> Result<(), ObjError> {
    splineskin_core::atomic_write::write_atomically(path, to_obj_string(cage).as_bytes()).map_err(
        |source| ObjError::Write {
            file: path.display().to_string(),
            source,
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn err(text: &str) -> String {
        parse_obj(text, "t.obj").unwrap_err().to_string()
    }

    #[test]
    fn obj_keeps_bare_vertices_and_file_order() {
        let cage = parse_obj(
            "v 9 9 9\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 2/7 3//1 -1\n",
            "t.obj",
        )
        .unwrap();
        assert_eq!(cage.n_vertices(), 4);
        assert_eq!(cage.positions()[0], [9.0, 9.0, 9.0]);
        assert_eq!(cage.face(0), &[1, 2, 3]);
    }

    #[test]
    fn obj_errors_name_line_and_expectation() {
        assert_eq!(
            err("v 0 0 0\nv 1 0 nan\n"),
            "t.obj:2: coordinate NaN; expected finite coordinates (no nan or inf)"
        );
        assert_eq!(
            err("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n"),
            "t.obj:4: vertex index 4; expected an index in 1..=3 (the number of `v` lines)"
        );
        assert_eq!(
            err("v 0 0 0\nv 1 0 0\nf 1 2\n"),
            "t.obj:3: face 0: 2 vertices; expected at least 3"
        );
        assert!(
            err("hello world\n").starts_with("t.obj:1: unknown or unsupported statement `hello`")
        );
        assert_eq!(
            err("v 0 0 0\n"),
            "t.obj: no `f` line; expected an OBJ file with at least one polygon"
        );
        assert!(
            err("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nt crease 2/1/0 0 1\n")
                .starts_with("t.obj:5: tag `crease` with 2 arguments after `2/1/0`")
        );
        assert!(
            err("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nt crease 2/1/0 0 7 1\n")
                .starts_with("t.obj:5: crease tag 0: vertices 0, 7")
        );
    }

    #[test]
    fn obj_round_trips_tags() {
        let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\n\
                    f 1 2 3 4\nf 2 5 6 3\n\
                    t crease 4/2/0 0 1 1 4 2.5 10\nt corner 1/1/0 5 0.1\nt hole 1/0/0 1\n\
                    t interpolateboundary 1/0/0 2\nt creasemethod 0/0/1 chaikin\n";
        let cage = parse_obj(text, "t.obj").unwrap();
        assert_eq!(cage.tags().creases.len(), 2);
        assert_eq!(cage.tags().creases[1].sharpness, 10.0);
        assert_eq!(cage.tags().corners[0].vertex, 5);
        assert_eq!(cage.tags().holes, vec![1]);
        assert_eq!(cage.tags().other.len(), 2);
        assert_eq!(cage.tags().other[1].strings, vec!["chaikin".to_owned()]);
        let again = parse_obj(&to_obj_string(&cage), "again.obj").unwrap();
        assert_eq!(again, cage);
    }
}
