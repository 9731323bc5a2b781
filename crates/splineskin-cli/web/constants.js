// Generated from Rust (splineskin_editor::page_constants): do not edit. After a change there,
// SPLINESKIN_WRITE_CONSTANTS=1 cargo test -p splineskin-cli page_constants writes it again.

/** Weight families solved on a triangulated domain (splineskin::scene::MeshFamily). */
export const MESH_FAMILIES = ['bbw', 'harmonic', 'biharmonic'];

/** Operator families, by ground truth (splineskin_editor::page_scene::defop_family). */
export const DEFOP_FAMILIES = ['defop-arap', 'defop-sarap'];

/** Training samples of an operator when the user has not chosen (DEFAULT_EDITOR_SAMPLES). */
export const DEFAULT_DEFOP_SAMPLES = 100;

/** Most training samples the routes take (MAX_EDITOR_SAMPLES). */
export const MAX_DEFOP_SAMPLES = 5000;

/** Handle bases of an operator (splineskin::defop::HandleBasisKind). */
export const HANDLE_BASIS_KINDS = ['linear', 'quadratic', 'cubic', 'tps'];

/** Junction kinds a click on a junction marker cycles through (splineskin::drawing::JointKind). */
export const JUNCTION_KINDS = ['C0', 'C1', 'G1', 'angle'];

/** Easings of a keyframe, in menu order (splineskin::animation::Easing). */
export const EASINGS = ['linear', 'ease-in', 'ease-out', 'ease-in-out', 'hold'];

/** Frames per second of an animation that names none. */
export const DEFAULT_FPS = 30;

/** Most frames per second of an animation. */
export const MAX_FPS = 1000;

/** The art-shaped domain's margin, a fraction of the diagonal: its default (splineskin::domain). */
export const DEFAULT_MARGIN = 0.01;

/** The largest margin (splineskin::domain::MAX_MARGIN). */
export const MAX_MARGIN = 1;

/** Most poses one refinement request measures (MAX_REFINE_POSES). */
export const MAX_REFINE_POSES = 64;

/** The attribute marking each imported element of the shown document (ELEMENT_MARKER). */
export const ELEMENT_MARKER = 'data-splineskin-element';

/** The attribute marking each carried text and image of the shown document (CARRIED_MARKER). */
export const CARRIED_MARKER = 'data-splineskin-carried';

/** The attribute marking each element's own copy of a user-space paint server (PAINT_MARKER). */
export const PAINT_MARKER = 'data-splineskin-paint';

/** How much better a reflection must fit an element's region than a rotation to be its stroke frame (splineskin::drawing::follow::REFLECTION_MARGIN). */
export const REFLECTION_MARGIN = 1.25;
