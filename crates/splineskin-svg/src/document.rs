//! What reading and writing SVG share: the error type ([`SvgError`]) and the size limit
//! ([`MAX_SVG_BYTES`]), and inside the crate: checking the size (`check_size`), parsing XML
//! (`parse_xml`), naming elements in messages (`node_label`), the namespaces, lengths
//! (`user_length`) and the shortest exact number text (`push_number`, `matrix`).
//!
//! Every other module of this crate builds on this one; it imports none of them.

use kurbo::Affine;

/// Largest accepted SVG input: 64 MiB. Bigger documents are refused before parsing
/// ([`SvgError::TooLarge`]).
pub const MAX_SVG_BYTES: usize = 64 * 1024 * 1024;

/// Errors of SVG import and export. Every variant names the file (`"<svg text>"` when the
/// document did not come from a file), the element where there is one, and what was expected.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SvgError {
    /// The file could not be read.
    #[error("{file}: cannot read the file: {source}")]
    Io {
        /// The file.
        file: String,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// The input is bigger than [`MAX_SVG_BYTES`] (or expanding its `use` elements would make
    /// it more than four times that).
    #[error("{file}: {size} bytes is more than the limit of {limit} bytes")]
    TooLarge {
        /// The file.
        file: String,
        /// Its size in bytes.
        size: u64,
        /// The limit in bytes.
        limit: u64,
    },
    /// The input is empty or whitespace only.
    #[error("{file}: the document is empty; expected an <svg> document")]
    Empty {
        /// The file.
        file: String,
    },
    /// The file is not UTF-8 text.
    #[error("{file}: not UTF-8 text; expected an SVG document encoded as UTF-8")]
    NotUtf8 {
        /// The file.
        file: String,
    },
    /// The text is not well-formed XML.
    #[error("{file}:{line}:{column}: not well-formed XML: {message}")]
    Xml {
        /// The file.
        file: String,
        /// 1-based line of the error.
        line: u32,
        /// 1-based column of the error.
        column: u32,
        /// roxmltree's description.
        message: String,
    },
    /// The root element is not `<svg>` in the SVG namespace.
    #[error("{file}: the root element is <{found}>; expected <svg> in the SVG namespace")]
    NoSvgRoot {
        /// The file.
        file: String,
        /// The root element's name.
        found: String,
    },
    /// An attribute does not parse, or holds a non-finite or too large number.
    #[error(
        "{file}: {element}: attribute {attribute}=\"{value}\" is invalid: expected {expected}"
    )]
    InvalidAttribute {
        /// The file.
        file: String,
        /// The element, as `tag#id (line n)`.
        element: String,
        /// The attribute's name.
        attribute: String,
        /// The attribute's value (shortened if long).
        value: String,
        /// What was expected.
        expected: String,
    },
    /// A point is beyond [`MAX_COORDINATE`](crate::svg_in::MAX_COORDINATE) after transforms.
    #[error("{file}: {element}: coordinate {value} is beyond ±{limit} in root user units")]
    CoordinateOutOfRange {
        /// The file.
        file: String,
        /// The element.
        element: String,
        /// The offending coordinate.
        value: f64,
        /// The limit ([`MAX_COORDINATE`](crate::svg_in::MAX_COORDINATE)).
        limit: f64,
    },
    /// No path or shape of the document is rendered, or every one is degenerate.
    #[error(
        "{file}: no paths: expected at least one rendered path, rect, circle, ellipse, line, \
         polyline or polygon with at least one segment{}",
        why.iter().map(|w| format!("; {w}")).collect::<String>()
    )]
    NoPaths {
        /// The file.
        file: String,
        /// What left the document without a path, when known: path data drawn up to its
        /// first error, where nothing comes before it.
        why: Vec<String>,
    },
    /// usvg refused the document (e.g. no valid size).
    #[error("{file}: usvg cannot read the document: {message}")]
    Usvg {
        /// The file.
        file: String,
        /// usvg's description.
        message: String,
    },
    /// A construct this version cannot import or export.
    #[error("{file}: {element}: unsupported: {what}")]
    Unsupported {
        /// The file.
        file: String,
        /// The element.
        element: String,
        /// What is not supported.
        what: String,
    },
    /// Export: the number of points is not `drawing.n_points()`.
    #[error("{file}: expected {expected} deformed points (drawing.n_points()), got {found}")]
    PointCount {
        /// The file.
        file: String,
        /// `drawing.n_points()`.
        expected: usize,
        /// The length given.
        found: usize,
    },
    /// Export: a deformed point is NaN or infinite.
    #[error(
        "{file}: deformed point {index} ({element}) is not finite; expected finite coordinates"
    )]
    NonFinitePoint {
        /// The file.
        file: String,
        /// The element the point belongs to.
        element: String,
        /// Index into the flat point buffer.
        index: usize,
    },
    /// Export: an element's local → root transform cannot be inverted.
    #[error(
        "{file}: {element}: its transform is singular; cannot express points in its coordinates"
    )]
    SingularTransform {
        /// The file.
        file: String,
        /// The element.
        element: String,
    },
    /// Export: the drawing's paths no longer match the document they came from.
    #[error("{file}: the drawing does not match its SVG source: {what}")]
    SourceMismatch {
        /// The file.
        file: String,
        /// What differs.
        what: String,
    },
    /// An internal invariant failed: a bug in splineskin.
    #[error("{file}: internal error (a bug in splineskin, please report it): {what}")]
    Internal {
        /// The file.
        file: String,
        /// What went wrong.
        what: String,
    },
}

/// [`SvgError::TooLarge`] if `size` bytes of the document `file` are more than
/// [`MAX_SVG_BYTES`].
pub(crate) fn check_size(file: &str, size: u64) -> Result<(), SvgError> {
    if size > MAX_SVG_BYTES as u64 {
        return Err(SvgError::TooLarge {
            file: file.to_string(),
            size,
            limit: MAX_SVG_BYTES as u64,
        });
    }
    Ok(())
}

/// roxmltree options shared by import and export (DTDs allowed, as usvg does).
pub(crate) fn xml_options<'i>() -> roxmltree::ParsingOptions<'i> {
    roxmltree::ParsingOptions {
        allow_dtd: true,
        ..Default::default()
    }
}

/// Parses `text` as XML, mapping errors to [`SvgError::Xml`].
pub(crate) fn parse_xml<'i>(
    text: &'i str,
    origin: &str,
) -> Result<roxmltree::Document<'i>, SvgError> {
    roxmltree::Document::parse_with_options(text, xml_options()).map_err(|e| {
        let pos = e.pos();
        let (line, column, message) = match e {
            // The parser places these at 1:1; the file ends where they are found.
            roxmltree::Error::UnexpectedEndOfStream | roxmltree::Error::UnclosedRootNode => {
                let (line, column) = end_position(text);
                (
                    line,
                    column,
                    format!("{e} (the file ends here: is it cut short?)"),
                )
            }
            _ => (pos.row, pos.col, e.to_string()),
        };
        SvgError::Xml {
            file: origin.to_string(),
            line,
            column,
            message,
        }
    })
}

/// The line and column (1-based, in characters) just past the end of `text`.
fn end_position(text: &str) -> (u32, u32) {
    let line = 1 + text.matches('\n').count();
    let last = text.rsplit('\n').next().unwrap_or("");
    let to_u32 = |n: usize| u32::try_from(n).unwrap_or(u32::MAX);
    (to_u32(line), to_u32(last.chars().count() + 1))
}

/// A user style sheet that shows every element usvg would leave out for `display: none`
/// (an injected `!important` rule comes first and wins over the document's own rules, as in
/// usvg's cascade): what import reads hidden layers with.
pub(crate) const SHOW_HIDDEN_CSS: &str = "* { display: inline !important; }";

/// `tag#id (line n)` for an element node.
pub(crate) fn node_label(doc: &roxmltree::Document, node: roxmltree::Node) -> String {
    let line = doc.text_pos_at(node.range().start).row;
    match node.attribute("id") {
        Some(id) => format!("{}#{} (line {line})", node.tag_name().name(), id),
        None => format!("{} (line {line})", node.tag_name().name()),
    }
}

/// The SVG namespace.
pub(crate) const SVG_NS: &str = "http://www.w3.org/2000/svg";

/// The XLink namespace (`xlink:href`).
pub(crate) const XLINK_NS: &str = "http://www.w3.org/1999/xlink";

/// The XML namespace (`xml:id`).
pub(crate) const XML_NS: &str = "http://www.w3.org/XML/1998/namespace";

/// `matrix(a b c d e f)` of an affine map, numbers in their shortest round-trip form.
pub(crate) fn matrix(t: Affine) -> String {
    let c = t.as_coeffs();
    let mut s = String::from("matrix(");
    push_numbers(&mut s, &c);
    s.push(')');
    s
}

/// Appends numbers separated by single spaces (a leading space is the caller's business).
pub(crate) fn push_numbers(out: &mut String, values: &[f64]) {
    for (i, &v) in values.iter().enumerate() {
        if i > 0 {
            out.push(' ');
        }
        push_number(out, v);
    }
}

/// Appends `v` in the shortest text that parses back to the same `f64`: the shorter of Rust's
/// shortest round-trip decimal (`{}`) and exponent (`{:e}`) forms; `0` for ±0.
pub(crate) fn push_number(out: &mut String, v: f64) {
    if v == 0.0 {
        out.push('0');
        return;
    }
    let plain = format!("{v}");
    let exp = format!("{v:e}");
    out.push_str(if exp.len() < plain.len() {
        &exp
    } else {
        &plain
    });
}

/// [`push_number`] as a `String`.
pub(crate) fn number(v: f64) -> String {
    let mut s = String::new();
    push_number(&mut s, v);
    s
}

/// Whether `node` is an element in the SVG namespace (or in none, as usvg accepts).
pub(crate) fn is_svg_element(node: roxmltree::Node) -> bool {
    node.is_element() && matches!(node.tag_name().namespace(), None | Some(SVG_NS))
}

/// The document's `<text>` elements that are not inside another one, in document order: what
/// text-to-outlines replaces and what a Lottie animation leaves out.
pub(crate) fn outermost_texts<'a, 'input>(
    doc: &'a roxmltree::Document<'input>,
) -> impl Iterator<Item = roxmltree::Node<'a, 'input>> {
    doc.descendants()
        .filter(|n| is_svg_element(*n) && n.tag_name().name() == "text")
        .filter(|n| !n.ancestors().skip(1).any(|a| a.tag_name().name() == "text"))
}

/// A `<length>` in user units: numbers, `px`, `in`, `cm`, `mm`, `pt`, `pc` (96 dpi) and
/// percentages of `percent_base`; `em`/`ex` are refused (they need the font size).
pub(crate) fn user_length(value: &str, percent_base: f64) -> Result<f64, String> {
    use svgtypes::LengthUnit as U;
    let length = <svgtypes::Length as std::str::FromStr>::from_str(value)
        .map_err(|e| format!("a length ({e})"))?;
    let n = length.number;
    Ok(match length.unit {
        U::None | U::Px => n,
        U::In => n * 96.0,
        U::Cm => n * 96.0 / 2.54,
        U::Mm => n * 96.0 / 25.4,
        U::Pt => n * 4.0 / 3.0,
        U::Pc => n * 16.0,
        U::Percent => n / 100.0 * percent_base,
        U::Em | U::Ex => return Err("a length without em/ex units".to_string()),
    })
}

/// A prefix for synthetic ids that no id of the document starts with.
pub(crate) fn unique_prefix(doc: &roxmltree::Document) -> String {
    let mut prefix = String::from("splineskin-");
    while doc
        .descendants()
        .filter_map(|n| n.attribute("id"))
        .any(|id| id.starts_with(&prefix))
    {
        prefix.push('x');
    }
    prefix
}
