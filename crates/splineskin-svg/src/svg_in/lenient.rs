//! A document read as a browser reads it, before anything else sees it: what chromium would
//! draw differently from what usvg reads (or refuses) is rewritten into the text chromium's
//! reading means, each change with a warning naming the file, the element and what was done.
//!
//! - **Internal DTD entities** (`<!DOCTYPE svg [<!ENTITY st0 "fill:red">]>`, as Adobe
//!   Illustrator writes them): every reference to a general entity declared in the internal
//!   subset is replaced by its replacement text (in attribute values with `<`, `&` of markup
//!   and the delimiting quote escaped), and the subset is dropped (XML 1.0, §4.4 "XML
//!   Processor Treatment of Entities"). At most [`MAX_ENTITY_DEPTH`] levels of nesting, and the
//!   expanded text at most [`MAX_SVG_BYTES`].
//! - **Lengths in CSS units** usvg does not know are written in user units, in geometry
//!   attributes and in `stroke-width` and `font-size` (CSS Values 4, §6.1, §6.2): `rem` (the
//!   root element's `font-size`, else 16 px), `vw`, `vh`, `vi`, `vb`, `vmin`, `vmax`
//!   (hundredths of the root viewport: its `width` and `height`, else its `viewBox`'s; `vi` and
//!   `vb` as `vw` and `vh` in horizontal writing) and `Q` (a quarter millimetre, 96/101.6 px)
//!   exactly; the units of font metrics, `ch`, `ic`, `cap`, `lh` and `rlh`, by the fallbacks CSS
//!   gives where the font cannot be measured (§6.1.1: `ch` ½ em, `ic` 1 em, `cap` the ascent,
//!   taken as 0.8 em; `lh` and `rlh` the `normal` line height, taken as 1.2 em of the element's
//!   and of the root's font size), with a warning that browsers measure the font instead.
//! - **Invalid attribute values** are ignored as browsers ignore them (SVG 2, §4.4 "Error
//!   handling": an invalid presentation attribute or geometry property value is as if not
//!   given): a length that is not a length (`width="44mmx"`, `x="inherit"`: CSS-wide keywords
//!   are not allowed in attributes), a `transform`, `viewBox` (negative size) or
//!   `preserveAspectRatio` that does not parse. The attribute is removed.
//! - **`points` lists**: an odd last coordinate is dropped; a list with an error draws nothing
//!   (SVG 2, §10.6 asks for the points before the error, as for path data, but chromium draws
//!   nothing of such an element, and what chromium draws is what is matched here).
//!
//! What is refused still: a document with nothing to draw, what usvg refuses, numbers beyond
//! the import's range (`MAX_COORDINATE`), a `viewBox` of zero size (it disables rendering).

use std::borrow::Cow;
use std::collections::HashMap;
use std::str::FromStr;

use super::validate::{length_attributes, shorten};
use crate::document::{node_label, parse_xml, SvgError, MAX_SVG_BYTES};

/// Deepest nesting of entity references expanded: 16.
pub const MAX_ENTITY_DEPTH: usize = 16;

/// `font-size` of the root element when it states none (CSS `medium`): 16 px.
const ROOT_FONT_SIZE: f64 = 16.0;

/// `text` as a browser reads it, and a warning per change (module doc). Borrowed when nothing
/// changes.
pub(crate) fn browser_reading<'t>(
    text: &'t str,
    origin: &str,
) -> Result<(Cow<'t, str>, Vec<String>), SvgError> {
    let mut warnings = Vec::new();
    let expanded = expand_entities(text, origin, &mut warnings)?;
    let current: &str = expanded.as_deref().unwrap_or(text);
    // Text that does not parse is left to the reader, whose error says why.
    let edits = match parse_xml(current, origin) {
        Ok(doc) => attribute_edits(&doc, origin, &mut warnings),
        Err(_) => Vec::new(),
    };
    if edits.is_empty() {
        return Ok((
            match expanded {
                Some(e) => Cow::Owned(e),
                None => Cow::Borrowed(text),
            },
            warnings,
        ));
    }
    let mut out = String::with_capacity(current.len());
    let mut at = 0;
    for (range, replacement) in edits {
        out.push_str(&current[at..range.start]);
        out.push_str(&replacement);
        at = range.end;
    }
    out.push_str(&current[at..]);
    Ok((Cow::Owned(out), warnings))
}

// ---------------------------------------------------------------------------------------------
// Attributes

/// Byte-range replacements of attribute text (in document order), with their warnings.
fn attribute_edits(
    doc: &roxmltree::Document,
    origin: &str,
    warnings: &mut Vec<String>,
) -> Vec<(std::ops::Range<usize>, String)> {
    let units = Units::of(doc.root_element());
    let mut edits = Vec::new();
    for node in doc
        .descendants()
        .filter(|n| crate::document::is_svg_element(*n))
    {
        let tag = node.tag_name().name();
        for attr in node.attributes().filter(|a| a.namespace().is_none()) {
            let (name, value) = (attr.name(), attr.value());
            let font_size = || font_size_of(node, &units);
            let parent_font_size = || {
                node.parent_element()
                    .map_or(ROOT_FONT_SIZE, |p| font_size_of(p, &units))
            };
            let sizes = FontSizes {
                own: &font_size,
                parent: &parent_font_size,
            };
            let Some(fix) = attribute_fix(tag, name, value, &units, &sizes) else {
                continue;
            };
            let element = node_label(doc, node);
            let shown = shorten(value);
            match fix {
                Fix::Remove(why) => {
                    warnings.push(format!(
                        "{origin}: {element}: attribute {name}=\"{shown}\" ignored ({why}), as \
                         browsers ignore it"
                    ));
                    edits.push((attr.range(), String::new()));
                }
                Fix::Value(new, why) => {
                    warnings.push(format!(
                        "{origin}: {element}: attribute {name}=\"{shown}\" read as \
                         {name}=\"{new}\" ({why}), as browsers read it"
                    ));
                    edits.push((attr.range_value(), new));
                }
            }
        }
    }
    edits.sort_by_key(|(r, _)| r.start);
    edits
}

/// What becomes of one attribute.
enum Fix {
    /// Removed, because of what (an invalid value).
    Remove(String),
    /// Its value replaced, because of what.
    Value(String, String),
}

/// An element's font size and its parent's, computed when asked.
struct FontSizes<'a> {
    own: &'a dyn Fn() -> f64,
    parent: &'a dyn Fn() -> f64,
}

/// The fix attribute `name="value"` of a `tag` element (whose font sizes `sizes` gives) needs,
/// if any.
fn attribute_fix(
    tag: &str,
    name: &str,
    value: &str,
    units: &Units,
    sizes: &FontSizes,
) -> Option<Fix> {
    let (font_size, parent_font_size) = (sizes.own, sizes.parent);
    match name {
        // Only what does not parse: numbers beyond the import's range stay refused.
        "transform" => svgtypes::TransformListParser::from(value)
            .any(|t| t.is_err())
            .then(|| Fix::Remove("not a transform list".into())),
        "viewBox" if matches!(tag, "svg" | "symbol" | "marker" | "pattern" | "view") => {
            let numbers: Result<Vec<f64>, _> = svgtypes::NumberListParser::from(value).collect();
            match numbers.as_deref() {
                // Zero disables rendering: left to the reader, which refuses it.
                Ok([_, _, w, h]) if *w == 0.0 || *h == 0.0 => None,
                Ok([_, _, w, h]) if *w < 0.0 || *h < 0.0 => {
                    Some(Fix::Remove("a negative width or height".into()))
                }
                Ok([_, _, _, _]) => None,
                _ => Some(Fix::Remove("not four numbers".into())),
            }
        }
        "preserveAspectRatio" => svgtypes::AspectRatio::from_str(value)
            .is_err()
            .then(|| Fix::Remove("not [defer] <align> [meet|slice]".into())),
        "points" if matches!(tag, "polyline" | "polygon") => points_fix(value),
        "stroke-width" => css_unit_fix(value, units, font_size),
        // Font-metric units in `font-size` are relative to the parent's font size.
        "font-size" => css_unit_fix(value, units, parent_font_size),
        _ if length_attributes(tag).contains(&name) => length_fix(name, value, units, font_size),
        _ => None,
    }
}

/// A geometry length: CSS units written in user units; anything else that is not a length
/// (nor `auto` where allowed) removed.
fn length_fix(name: &str, value: &str, units: &Units, font_size: &dyn Fn() -> f64) -> Option<Fix> {
    let auto_allowed = matches!(name, "rx" | "ry" | "width" | "height");
    if (auto_allowed && value.trim() == "auto") || svgtypes::Length::from_str(value).is_ok() {
        return None;
    }
    css_unit_fix(value, units, font_size).or_else(|| {
        let why = match value.trim() {
            "inherit" | "initial" | "unset" | "revert" | "revert-layer" => {
                "a CSS-wide keyword is not a value an attribute may take".to_string()
            }
            _ => "not a length".to_string(),
        };
        Some(Fix::Remove(why))
    })
}

/// CSS units usvg does not read (module doc), longest first where one ends another; matched
/// without regard to case, as CSS units are.
const CSS_UNITS: [&str; 13] = [
    "vmin", "vmax", "rem", "rlh", "cap", "vw", "vh", "vi", "vb", "ch", "ic", "lh", "q",
];

/// Ems per unit of font metrics, as CSS falls back when the font cannot be measured (module
/// doc), and how browsers measure it instead (for the warning).
fn font_metric(unit: &str) -> Option<(f64, &'static str)> {
    Some(match unit {
        "ch" => (0.5, "the advance of the font's \"0\""),
        "ic" => (1.0, "the advance of the font's \"水\""),
        "cap" => (0.8, "the font's cap height"),
        "lh" | "rlh" => (1.2, "the font's line spacing"),
        _ => return None,
    })
}

/// A length in one of [`CSS_UNITS`], written in user units; `font_size` gives the element's
/// (asked only for the units of font metrics).
fn css_unit_fix(value: &str, units: &Units, font_size: &dyn Fn() -> f64) -> Option<Fix> {
    let (user, unit, scale) = css_length(value, units, font_size)?;
    let why = match font_metric(unit) {
        Some((ems, measured)) => format!(
            "1{unit} taken as {ems} em = {}, the value CSS gives when the font cannot be \
             measured: browsers measure {measured}, which differs by font",
            crate::document::number(scale)
        ),
        None => format!("1{unit} = {}", crate::document::number(scale)),
    };
    user.is_finite()
        .then(|| Fix::Value(crate::document::number(user), why))
}

/// A length in one of [`CSS_UNITS`] in user units, its unit and user units per unit;
/// `font_size` gives the element's (for `font-size` itself, its parent's), asked only for the
/// units of font metrics.
fn css_length(
    value: &str,
    units: &Units,
    font_size: &dyn Fn() -> f64,
) -> Option<(f64, &'static str, f64)> {
    let v = value.trim().to_ascii_lowercase();
    let (number, unit) = CSS_UNITS
        .into_iter()
        .find_map(|u| Some((v.strip_suffix(u)?, u)))?;
    let unit = if unit == "q" { "Q" } else { unit };
    let number: f64 = number.trim_end().parse().ok()?;
    let scale = match font_metric(unit) {
        Some((ems, _)) => {
            ems * if unit == "rlh" {
                units.rem
            } else {
                font_size()
            }
        }
        None => units.scale(unit)?,
    };
    Some((number * scale, unit, scale))
}

/// User units per millimetre: 96 / 25.4 (CSS Values 4, §6.2: 1 in = 96 px = 25.4 mm).
const PX_PER_MM: f64 = 96.0 / 25.4;

/// The font size of `node` in user units: the nearest `font-size` of it or its ancestors that
/// reads, relative ones (`em`, `ex` as ½ em, `%`, the font metrics of [`CSS_UNITS`]) against
/// their parent's, else 16 (CSS `medium`).
fn font_size_of(node: roxmltree::Node, units: &Units) -> f64 {
    let mut chain: Vec<roxmltree::Node> = node.ancestors().filter(|n| n.is_element()).collect();
    chain.reverse();
    chain.iter().fold(ROOT_FONT_SIZE, |size, n| {
        let Some(value) = n
            .attribute("font-size")
            .or_else(|| style_property(n.attribute("style")?, "font-size"))
        else {
            return size;
        };
        let Ok(length) = svgtypes::Length::from_str(value) else {
            // A font size in font-metric units is relative to the parent's font size.
            let css = css_length(value, units, &|| size).map(|(user, _, _)| user);
            return css.filter(|v| v.is_finite() && *v > 0.0).unwrap_or(size);
        };
        let v = length.number;
        let absolute = match length.unit {
            svgtypes::LengthUnit::None | svgtypes::LengthUnit::Px => v,
            svgtypes::LengthUnit::Em => v * size,
            svgtypes::LengthUnit::Ex => v * size / 2.0,
            svgtypes::LengthUnit::Percent => v * size / 100.0,
            svgtypes::LengthUnit::In => v * 96.0,
            svgtypes::LengthUnit::Cm => v * 10.0 * PX_PER_MM,
            svgtypes::LengthUnit::Mm => v * PX_PER_MM,
            svgtypes::LengthUnit::Pt => v * 4.0 / 3.0,
            svgtypes::LengthUnit::Pc => v * 16.0,
        };
        if absolute.is_finite() && absolute > 0.0 {
            absolute
        } else {
            size
        }
    })
}

/// The root's font size and viewport, for CSS units.
struct Units {
    rem: f64,
    viewport: Option<(f64, f64)>,
}

impl Units {
    fn of(root: roxmltree::Node) -> Units {
        // A length in user units (unitless or px), positive.
        let user = |v: &str| {
            svgtypes::Length::from_str(v)
                .ok()
                .filter(|l| {
                    matches!(
                        l.unit,
                        svgtypes::LengthUnit::None | svgtypes::LengthUnit::Px
                    )
                })
                .map(|l| l.number)
                .filter(|v| v.is_finite() && *v > 0.0)
        };
        let font_size = root
            .attribute("font-size")
            .or_else(|| style_property(root.attribute("style")?, "font-size"))
            .and_then(user);
        let length = |name: &str| root.attribute(name).and_then(user);
        let view_box = root
            .attribute("viewBox")
            .and_then(|v| svgtypes::ViewBox::from_str(v).ok())
            .filter(|vb| vb.w > 0.0 && vb.h > 0.0);
        let viewport = match (length("width"), length("height"), view_box) {
            (Some(w), Some(h), _) => Some((w, h)),
            (_, _, Some(vb)) => Some((vb.w, vb.h)),
            _ => None,
        };
        Units {
            rem: font_size.unwrap_or(ROOT_FONT_SIZE),
            viewport,
        }
    }

    /// User units per `unit`, one of [`CSS_UNITS`] other than the font metrics (`None`
    /// without a viewport for the viewport units).
    fn scale(&self, unit: &str) -> Option<f64> {
        let (w, h) = match unit {
            "rem" => return Some(self.rem),
            "Q" => return Some(PX_PER_MM / 4.0),
            _ => self.viewport?,
        };
        Some(
            match unit {
                "vw" | "vi" => w,
                "vh" | "vb" => h,
                "vmin" => w.min(h),
                _ => w.max(h),
            } / 100.0,
        )
    }
}

/// The value of `property` in a `style` attribute's declarations, if any.
fn style_property<'a>(style: &'a str, property: &str) -> Option<&'a str> {
    style.split(';').find_map(|d| {
        let (name, value) = d.split_once(':')?;
        (name.trim() == property).then(|| value.trim())
    })
}

/// A `points` list with an error read as empty (chromium draws nothing of the element), or
/// with an odd last coordinate dropped (written `x,y x,y …`).
fn points_fix(value: &str) -> Option<Fix> {
    let numbers: Result<Vec<f64>, _> = svgtypes::NumberListParser::from(value).collect();
    let numbers = match numbers {
        Ok(numbers) => numbers,
        Err(e) => {
            return Some(Fix::Value(
                String::new(),
                format!("an error in the list ({e}): nothing drawn"),
            ))
        }
    };
    if numbers.len() % 2 == 0 {
        return None;
    }
    let pairs: Vec<String> = numbers
        .chunks_exact(2)
        .map(|p| {
            format!(
                "{},{}",
                crate::document::number(p[0]),
                crate::document::number(p[1])
            )
        })
        .collect();
    Some(Fix::Value(
        pairs.join(" "),
        format!("{} coordinates: the odd last one dropped", numbers.len()),
    ))
}

// ---------------------------------------------------------------------------------------------
// Entities

/// The text with the general entities of its internal DTD subset expanded and the subset
/// dropped (module doc); `None` when it declares none.
fn expand_entities(
    text: &str,
    origin: &str,
    warnings: &mut Vec<String>,
) -> Result<Option<String>, SvgError> {
    let Some(doctype) = text.find("<!DOCTYPE") else {
        return Ok(None);
    };
    let Some((open, close)) = internal_subset(text, doctype) else {
        return Ok(None);
    };
    let entities = declarations(&text[open + 1..close]);
    if entities.is_empty() {
        return Ok(None);
    }
    // The DOCTYPE up to its subset, closed; the subset and what follows it up to `>` dropped.
    let mut out = String::with_capacity(text.len());
    out.push_str(&text[..open]);
    out.push('>');
    let after = close + 1 + text[close + 1..].find('>').map_or(0, |i| i + 1);
    let mut expander = Expander {
        entities: &entities,
        origin,
        out,
    };
    expander.body(&text[after..])?;
    let mut names: Vec<&str> = entities.keys().copied().collect();
    names.sort_unstable();
    warnings.push(format!(
        "{origin}: the entities of its DOCTYPE ({}) expanded in the text, as XML readers \
         expand them",
        names.join(", ")
    ));
    Ok(Some(expander.out))
}

/// The byte offsets of the `[` and `]` of the internal subset of the DOCTYPE at `doctype`.
fn internal_subset(text: &str, doctype: usize) -> Option<(usize, usize)> {
    let bytes = text.as_bytes();
    let mut i = doctype + "<!DOCTYPE".len();
    let mut quote = None;
    let mut open = None;
    while i < bytes.len() {
        let c = bytes[i];
        match (quote, open) {
            (Some(q), _) if c == q => quote = None,
            (Some(_), _) => {}
            (None, _) if c == b'"' || c == b'\'' => quote = Some(c),
            (None, None) if c == b'[' => open = Some(i),
            (None, None) if c == b'>' => return None,
            (None, Some(o)) if c == b']' => return Some((o, i)),
            _ => {}
        }
        i += 1;
    }
    None
}

/// The general internal entities declared in an internal subset: name → replacement text
/// (character references in it replaced, as XML does when it reads the declaration).
fn declarations(subset: &str) -> HashMap<&str, String> {
    let mut entities = HashMap::new();
    let mut rest = subset;
    while let Some(start) = rest.find("<!ENTITY") {
        rest = &rest[start + "<!ENTITY".len()..];
        let body = rest.trim_start();
        if body.starts_with('%') {
            continue; // a parameter entity: for the DTD, not the document
        }
        let name_end = body.find(|c: char| c.is_whitespace()).unwrap_or(body.len());
        let name = &body[..name_end];
        let value = body[name_end..].trim_start();
        let Some(q) = value.chars().next().filter(|c| *c == '"' || *c == '\'') else {
            continue; // external (SYSTEM or PUBLIC): not read
        };
        let Some(end) = value[1..].find(q) else {
            break;
        };
        entities
            .entry(name)
            .or_insert_with(|| character_references(&value[1..1 + end]));
        rest = &value[1 + end..];
    }
    entities
}

/// `s` with its character references (`&#60;`, `&#x3C;`) replaced by their characters.
fn character_references(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    let mut rest = s;
    while let Some(i) = rest.find("&#") {
        out.push_str(&rest[..i]);
        let after = &rest[i + 2..];
        let parsed = after.find(';').and_then(|end| {
            let code = match after.strip_prefix(['x', 'X']) {
                Some(hex) => u32::from_str_radix(&hex[..end - 1], 16).ok(),
                None => after[..end].parse().ok(),
            };
            Some((char::from_u32(code?)?, end))
        });
        match parsed {
            Some((c, end)) => {
                out.push(c);
                rest = &after[end + 1..];
            }
            None => {
                out.push_str("&#");
                rest = after;
            }
        }
    }
    out.push_str(rest);
    out
}

/// Writes a document body with entity references expanded.
struct Expander<'e> {
    entities: &'e HashMap<&'e str, String>,
    origin: &'e str,
    out: String,
}

impl Expander<'_> {
    /// The document after its DOCTYPE: markup copied, references expanded (in content as
    /// markup, in attribute values escaped).
    fn body(&mut self, text: &str) -> Result<(), SvgError> {
        let mut i = 0;
        let bytes = text.as_bytes();
        while i < bytes.len() {
            let rest = &text[i..];
            if let Some(skip) = ["<!--", "<![CDATA[", "<?"]
                .into_iter()
                .zip(["-->", "]]>", "?>"])
                .find_map(|(open, close)| {
                    rest.starts_with(open)
                        .then(|| rest.find(close).map_or(rest.len(), |e| e + close.len()))
                })
            {
                self.out.push_str(&rest[..skip]);
                i += skip;
            } else if rest.starts_with('<') {
                i += self.tag(rest)?;
            } else if rest.starts_with('&') {
                i += self.reference(rest, None, 0)?;
            } else {
                let next = rest.find(['<', '&']).unwrap_or(rest.len());
                self.out.push_str(&rest[..next]);
                i += next;
            }
        }
        Ok(())
    }

    /// One tag at the start of `rest`, references in its attribute values expanded; its length.
    fn tag(&mut self, rest: &str) -> Result<usize, SvgError> {
        let bytes = rest.as_bytes();
        let mut i = 0;
        let mut quote: Option<u8> = None;
        while i < bytes.len() {
            let c = bytes[i];
            match quote {
                Some(q) if c == q => {
                    quote = None;
                    self.out.push(c as char);
                    i += 1;
                }
                Some(q) if c == b'&' => i += self.reference(&rest[i..], Some(q), 0)?,
                None if c == b'"' || c == b'\'' => {
                    quote = Some(c);
                    self.out.push(c as char);
                    i += 1;
                }
                None if c == b'>' => {
                    self.out.push('>');
                    return Ok(i + 1);
                }
                _ => {
                    // Up to the next delimiter (all ASCII, so the cut is a char boundary);
                    // past this one when it is a delimiter copied as text (a quote of the
                    // other kind, `>` in a value, `&` outside one).
                    let from = if c.is_ascii() { i + 1 } else { i };
                    let next = rest[from..]
                        .find(['"', '\'', '&', '>'])
                        .map_or(rest.len(), |n| from + n);
                    self.out.push_str(&rest[i..next]);
                    i = next;
                }
            }
        }
        Ok(rest.len())
    }

    /// The reference at the start of `rest` (`&name;`), expanded if it names a declared
    /// entity (in an attribute value delimited by `quote`, escaped), else copied; its length.
    fn reference(
        &mut self,
        rest: &str,
        quote: Option<u8>,
        depth: usize,
    ) -> Result<usize, SvgError> {
        let end = rest[1..]
            .find(|c: char| c == ';' || c == '<' || c == '&' || c.is_whitespace())
            .map(|e| e + 1);
        let name = end
            .filter(|&e| rest.as_bytes()[e] == b';')
            .map(|e| &rest[1..e]);
        let Some((name, value)) = name.and_then(|n| Some((n, self.entities.get(n)?))) else {
            self.out.push('&');
            return Ok(1);
        };
        if depth >= MAX_ENTITY_DEPTH {
            return Err(SvgError::Unsupported {
                file: self.origin.to_string(),
                element: format!("entity &{name};"),
                what: format!("entities nested more than {MAX_ENTITY_DEPTH} deep"),
            });
        }
        self.expand(value, quote, depth + 1)?;
        if self.out.len() > MAX_SVG_BYTES {
            return Err(SvgError::TooLarge {
                file: self.origin.to_string(),
                size: self.out.len() as u64,
                limit: MAX_SVG_BYTES as u64,
            });
        }
        Ok(name.len() + 2)
    }

    /// Writes replacement text `value`, its own references expanded.
    fn expand(&mut self, value: &str, quote: Option<u8>, depth: usize) -> Result<(), SvgError> {
        let mut rest = value;
        while !rest.is_empty() {
            if rest.starts_with('&') {
                let n = self.reference(rest, quote, depth)?;
                rest = &rest[n..];
                continue;
            }
            let next = rest.find('&').unwrap_or(rest.len());
            let chunk = &rest[..next];
            match quote {
                None => self.out.push_str(chunk),
                Some(q) => {
                    for c in chunk.chars() {
                        match c {
                            '<' => self.out.push_str("&lt;"),
                            '"' if q == b'"' => self.out.push_str("&quot;"),
                            '\'' if q == b'\'' => self.out.push_str("&apos;"),
                            c => self.out.push(c),
                        }
                    }
                }
            }
            rest = &rest[next..];
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(text: &str) -> (String, Vec<String>) {
        let (t, w) = browser_reading(text, "t.svg").unwrap();
        (t.into_owned(), w)
    }

    #[test]
    fn lenient_entities_expand_in_content_and_attributes() {
        let text = "<?xml version=\"1.0\"?>\n<!DOCTYPE svg [\n<!ENTITY ns \"http://www.w3.org/2000/svg\">\n\
            <!ENTITY st 'fill:\"red\"'>\n<!ENTITY dot \"<circle r='&one;'/>\">\n<!ENTITY one \"1\">\n]>\n\
            <svg xmlns=\"&ns;\" style=\"&st;\">&dot;<!-- &st; --></svg>";
        let (out, warnings) = read(text);
        assert_eq!(
            out,
            "<?xml version=\"1.0\"?>\n<!DOCTYPE svg >\n<svg xmlns=\"http://www.w3.org/2000/svg\" \
             style=\"fill:&quot;red&quot;\"><circle r='1'/><!-- &st; --></svg>"
        );
        assert_eq!(warnings.len(), 1, "{warnings:?}");
    }

    #[test]
    fn lenient_entities_refuse_a_billion_laughs() {
        let mut dtd = String::from("<!ENTITY a0 \"lol\">");
        for k in 1..12 {
            let refs = format!("&a{};", k - 1).repeat(10);
            dtd.push_str(&format!("<!ENTITY a{k} \"{refs}\">"));
        }
        let text =
            format!("<!DOCTYPE svg [{dtd}]><svg xmlns=\"http://www.w3.org/2000/svg\">&a11;</svg>");
        let err = browser_reading(&text, "laughs.svg")
            .unwrap_err()
            .to_string();
        assert!(err.starts_with("laughs.svg: "), "{err}");
        assert!(err.contains("limit"), "{err}");
    }

    #[test]
    fn lenient_points_drop_an_odd_coordinate_and_draw_nothing_in_error() {
        let fix = |v: &str| match points_fix(v) {
            Some(Fix::Value(v, _)) => Some(v),
            _ => None,
        };
        assert_eq!(
            fix("10,10 90,10 90,50 50").as_deref(),
            Some("10,10 90,10 90,50")
        );
        // As chromium: a list with an error draws nothing.
        assert_eq!(fix("10,60 40,60 40,90 x 10,90").as_deref(), Some(""));
        assert_eq!(fix("1-2-3-4-5").as_deref(), Some("1,-2 -3,-4"));
        assert_eq!(fix("10,10 20,20"), None);
    }

    #[test]
    fn lenient_lengths_in_css_units_and_invalid_ones() {
        let text = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"200\" height=\"100\" \
            style=\"font-size:20px\"><rect x=\"inherit\" width=\"2rem\" height=\"10vh\" \
            stroke-width=\"1vmin\"/><rect width=\"44mmx\" transform=\"rotate(\"/></svg>";
        let (out, warnings) = read(text);
        assert_eq!(
            out,
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"200\" height=\"100\" \
             style=\"font-size:20px\"><rect  width=\"40\" height=\"10\" stroke-width=\"1\"/>\
             <rect  /></svg>"
        );
        assert_eq!(warnings.len(), 6, "{warnings:#?}");
        assert!(warnings[0].starts_with("t.svg: rect (line 1): attribute x=\"inherit\" ignored"));
    }

    #[test]
    fn lenient_font_metric_units_take_the_css_fallbacks_of_the_element_font_size() {
        // Root font size 2rem = 32; the group's 50 %, 16; the inner rect's own 3ch is of its
        // parent's, 24, and its height in lh of that 24.
        let text = "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 100 100\" \
            font-size=\"2rem\"><rect width=\"10ch\" height=\"1cap\" x=\"1lh\"/>\
            <g font-size=\"50%\"><rect width=\"2rlh\" height=\"2LH\" font-size=\"3ch\"/></g></svg>";
        let (out, warnings) = read(text);
        assert_eq!(
            out,
            "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 100 100\" \
             font-size=\"32\"><rect width=\"160\" height=\"25.6\" x=\"38.4\"/>\
             <g font-size=\"50%\"><rect width=\"38.4\" height=\"57.599999999999994\" font-size=\"24\"/></g></svg>"
        );
        assert!(
            warnings[1].contains(
                "1ch taken as 0.5 em = 16, the value CSS gives when the font \
                 cannot be measured: browsers measure the advance of the font's \"0\""
            ),
            "{warnings:#?}"
        );
    }
}
