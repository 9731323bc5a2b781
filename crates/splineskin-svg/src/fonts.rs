//! The fonts text is drawn and outlined with: the DejaVu Sans faces shipped in the `dejavu`
//! crate, and nothing from the system, so that a document renders the same on every machine.
//!
//! [`database`] holds DejaVu Sans in four faces (regular, bold, oblique, bold oblique: 2.74 MB
//! of TrueType data embedded in the binary) and names it as the family of every generic
//! family (`serif`, `sans-serif`, `monospace`, `cursive`, `fantasy`). usvg's font selection
//! tries the families of `font-family` in order and then `serif`, so **every** text is drawn in
//! DejaVu Sans, whatever family it names: a document that asks for Arial or Times gets the
//! same glyph shapes everywhere, at the size, weight and slant it asks for (other widths of a
//! named font, and its exact metrics, are not reproduced). Characters DejaVu Sans lacks (it
//! covers Latin, Greek, Cyrillic, Armenian, Georgian, Hebrew, Arabic subsets, arrows, box
//! drawing and many symbols; no CJK, no colour emoji) are not drawn.
//!
//! [`usvg_options`] are usvg options that use it; [`crate::render`] and the text-to-outlines
//! import ([`crate::svg_in::TextMode::Outlines`]) read documents with them.

#[cfg(feature = "fonts")]
use std::sync::{Arc, OnceLock};

#[cfg(feature = "fonts")]
use usvg::fontdb;

/// Whether this build has the fonts and text layout (the `fonts` feature): without them usvg
/// lays out no text, renders leave text out and the text-to-outlines import refuses (text is
/// still imported, kept and carried by the deformation: that reads the document's own text).
pub const HAS_FONTS: bool = cfg!(feature = "fonts");

/// The family every text is drawn in: `"DejaVu Sans"`.
pub const FAMILY: &str = "DejaVu Sans";

/// The font database of every render and of the text-to-outlines import: the four DejaVu Sans
/// faces of the `dejavu` crate, [`FAMILY`] set as every generic family. Built once (parsing
/// the faces' name tables takes well under a millisecond), then shared.
///
/// ```
/// let db = splineskin_svg::fonts::database();
/// # if !splineskin_svg::fonts::HAS_FONTS { return; }
/// assert_eq!(db.len(), 4);
/// let query = usvg::fontdb::Query {
///     families: &[usvg::fontdb::Family::Monospace],
///     weight: usvg::fontdb::Weight::BOLD,
///     ..Default::default()
/// };
/// let face = db.face(db.query(&query).unwrap()).unwrap();
/// assert_eq!(face.families[0].0, "DejaVu Sans");
/// assert_eq!(face.weight, usvg::fontdb::Weight::BOLD);
/// ```
#[cfg(feature = "fonts")]
pub fn database() -> Arc<fontdb::Database> {
    static DATABASE: OnceLock<Arc<fontdb::Database>> = OnceLock::new();
    DATABASE
        .get_or_init(|| {
            let mut db = fontdb::Database::new();
            for data in [
                dejavu::sans::regular(),
                dejavu::sans::bold(),
                dejavu::sans::oblique(),
                dejavu::sans::bold_oblique(),
            ] {
                db.load_font_source(fontdb::Source::Binary(Arc::new(data)));
            }
            db.set_serif_family(FAMILY);
            db.set_sans_serif_family(FAMILY);
            db.set_monospace_family(FAMILY);
            db.set_cursive_family(FAMILY);
            db.set_fantasy_family(FAMILY);
            Arc::new(db)
        })
        .clone()
}

/// usvg options that draw text with [`database`] ([`FAMILY`] also as the family of text that
/// names none) and keep usvg away from the file system: no resources directory, no image
/// loaded from a path; images embedded as `data:` URLs are decoded when `data_images` is set.
pub fn usvg_options(data_images: bool) -> usvg::Options<'static> {
    usvg::Options {
        resources_dir: None,
        font_family: FAMILY.to_string(),
        #[cfg(feature = "fonts")]
        fontdb: database(),
        image_href_resolver: usvg::ImageHrefResolver {
            resolve_data: if data_images {
                usvg::ImageHrefResolver::default_data_resolver()
            } else {
                Box::new(|_, _, _| None)
            },
            resolve_string: Box::new(|_, _| None),
        },
        ..usvg::Options::default()
    }
}
