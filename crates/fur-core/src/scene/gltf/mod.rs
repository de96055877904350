//! glTF 2.0 models, in (`.gltf` with its buffers and images, or `.glb`) and out (`.glb`):
//! the triangles of a scene merged into one [`Mesh`], and, when the body is skinned or
//! animated, its [`Rig`] (node hierarchy, joints, weights and clips).
//!
//! Reading trusts nothing in the file: every file is read through
//! [`crate::files::read_bounded`], every index is checked before use, and every accessor
//! is checked against its buffer view and buffer before anything is allocated for it,
//! so a hostile file costs at most a small multiple of its own size and never panics.
//! The `gltf` crate's own validation is not used: it indexes unchecked (a `POSITION`
//! naming a missing accessor panics inside it), and so does its `.glb` splitter on a
//! header length under 12; this module splits `.glb` files itself and reads the
//! deserialised JSON ([`gltf::json::Root`]) with checked look-ups.
//!
//! Conventions are glTF's and this project's alike: right-handed, +Y up, counter-
//! clockwise front faces, texture coordinates with (0, 0) at the image's top-left.

mod accessor;
mod animation;
mod builder;
mod document;
mod primitive;
mod read;
mod skin;
mod source;
mod tree;
mod uri;
mod write;

use std::path::Path;

use super::{Mesh, Rig};
use crate::error::{Error, Result};

pub use write::write_glb;

/// A body read from a glTF file.
#[derive(Clone, Debug, PartialEq)]
pub struct GltfBody {
    /// The triangles of the scene in their rest pose (a rigged body: skinned with every
    /// node at its rest transform), in the scene's world space.
    pub mesh: Mesh,
    /// The skeleton, skin and clips, vertex-aligned with `mesh`; `None` for a file with
    /// neither a skinned mesh nor an animation that moves one (just a mesh, like an OBJ).
    pub rig: Option<Rig>,
    /// What was ignored or could not be used (morph targets, cameras, unsupported
    /// extensions, a missing texture, ...), each naming the thing; not logged here.
    pub warnings: Vec<String>,
}

/// Reads a `.gltf` (with its `.bin` files and images beside it, or `data:` URIs) or a
/// `.glb` file: its default scene (or scene 0, or every root node when it has no
/// scenes), every mesh's triangle primitives (lists, strips and fans) merged into one
/// body, with the rig when it is skinned or animated (see [`GltfBody`]).
///
/// - Skinned primitives (a node with a skin, primitives with `JOINTS_0`/`WEIGHTS_0`)
///   ignore their node's transform: their file positions are the rig's bind positions
///   and the mesh holds them skinned at rest (`global_rest(joint) · inverseBindMatrix`).
///   Other primitives are placed by their node's global rest transform; in a rigged
///   body each such node gets a joint of its own, weighted 1.
/// - `Rig::nodes` are the scene's nodes, parents first, in file order where the file
///   already has parents first; a node that only holds a skinned mesh (a leaf that is
///   no joint) is left out: its transform has no effect. Unnamed nodes are `node{i}`.
/// - Weights are renormalised to sum 1 (sums already 1 within 1e-6 are kept bit for
///   bit, as are normals of unit length within 1e-5, so a written rig reads back
///   exactly); a sum of 0, a negative or non-finite weight, or a joint index past its
///   skin is an error.
/// - Clips keep their interpolation (STEP, LINEAR, CUBICSPLINE) and values; key times
///   must be finite and strictly increasing.
/// - Normals come from the file when every primitive has usable ones, otherwise from
///   the faces; texture coordinates (`TEXCOORD_0`) when every primitive has them. The
///   texture is the base colour texture of the first triangle primitive's material.
/// - Vertices are never dropped or merged (the rig is vertex-aligned); degenerate
///   triangles are dropped from the indices.
/// - Refused with an error naming the file and the problem: any `extensionsRequired`
///   (Draco, meshopt, ...), sparse accessors, URLs and absolute paths, data out of
///   bounds, a scene without triangles, more than 2²⁵ vertices once merged.
/// - Warnings (in [`GltfBody::warnings`]), each naming the thing: morph targets and
///   their weight channels, `JOINTS_1`/`WEIGHTS_1`, cameras, extensions used but not
///   required, primitives that are not triangles, a texture that cannot be used, and
///   what valid files hold but the `gltf` crate refuses (animation channels without a
///   target node, `extras` that are not objects), which is dropped.
pub fn load_gltf(path: &Path) -> Result<GltfBody> {
    let error = |message: String| Error::Model {
        path: path.to_path_buf(),
        message,
    };
    let bytes =
        crate::files::read_bounded(path, crate::files::MAX_MODEL_BYTES, "model").map_err(error)?;
    let mut warnings = Vec::new();
    let source = source::Source::open(bytes, path, &mut warnings).map_err(error)?;
    let (mesh, rig) = read::read_body(&source, &mut warnings).map_err(error)?;
    Ok(GltfBody {
        mesh,
        rig,
        warnings,
    })
}

/// The most vertices (and a proportional number of triangle corners and key values) a
/// file may add up to once its meshes are merged and instanced: a small file that
/// instances a large mesh on many nodes is refused before it fills the memory.
pub(crate) const MAX_VERTICES: usize = 1 << 25;
