//! Catmull–Clark subdivision surfaces with OpenSubdiv 3 semantics (DESIGN.md §3).
//!
//! A [`Cage`] is a control mesh with OpenSubdiv's subdivision tags (creases, corners, holes),
//! read from and written to OBJ with [`read_obj`] and [`write_obj`].
mod cage;
mod obj;

pub use cage::{
    Cage, CageError, CornerTag, CreaseTag, OtherTag, Point3, SubdivTags, SHARPNESS_INFINITE,
};
pub use obj::{parse_obj, read_obj, to_obj_string, write_obj, ObjError, MAX_OBJ_BYTES};
