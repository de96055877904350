//! glTF 2.0 input and output: skinned and animated bodies read from `.gltf` and `.glb`
//! files made here, written back with `write_glb`, and bad files refused with messages
//! that name the file and the problem. No device: `cargo test -p fur-core` runs them.

mod doc;
mod read;
mod refused;
mod round_trip;

use doc::*;
