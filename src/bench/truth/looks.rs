//! The looks each truth scene is drawn with besides its quality ladder: its own look
//! with one thing switched.

use crate::bench::quality::Look;
use fur_core::render::{LightingModel, Raster};

/// The looks switched one at a time, each against the scene's own drawing.
pub(super) const LOOKS: usize = 6;

/// The scene's look with one thing switched: the lighting model (alone, and with
/// shadows), shadows, the secondary highlight (Kajiya–Kay's look: under the Marschner
/// model, switched on Kajiya–Kay's drawing), thin-hair AA, the strand rasteriser.
/// Sample counts and lines
/// against ribbons are the rungs of a CPU driver's ladder (rung 1: 4× lines, rung 2: 1×
/// ribbons, rung 3: 1× lines), not drawn again here; a GPU's ladder has 4× lines and
/// the compute strands.
pub(super) fn looks(own: &Look) -> Vec<(String, Look)> {
    let with = |edit: &dyn Fn(&mut Look)| {
        let mut look = own.clone();
        edit(&mut look);
        look
    };
    let l = &own.lighting;
    let other = match l.model {
        LightingModel::KajiyaKay => LightingModel::Marschner,
        LightingModel::Marschner => LightingModel::KajiyaKay,
    };
    let switched = |on: bool, what: &str| format!("{what} {}", if on { "off" } else { "on" });
    let looks = vec![
        (
            format!("{} lighting", other.label()),
            with(&|k| k.lighting.model = other),
        ),
        (
            format!("{} lighting, shadows on", other.label()),
            with(&|k| {
                k.lighting.model = other;
                k.lighting.shadows.enabled = true;
            }),
        ),
        (
            switched(l.shadows.enabled, "shadows"),
            with(&|k| k.lighting.shadows.enabled = !l.shadows.enabled),
        ),
        match l.model {
            LightingModel::KajiyaKay => (
                switched(l.highlights.secondary, "secondary highlight"),
                with(&|k| k.lighting.highlights.secondary = !l.highlights.secondary),
            ),
            LightingModel::Marschner => (
                format!(
                    "{} lighting, {}",
                    other.label(),
                    switched(l.highlights.secondary, "secondary highlight")
                ),
                with(&|k| {
                    k.lighting.model = other;
                    k.lighting.highlights.secondary = !l.highlights.secondary;
                }),
            ),
        },
        (
            switched(own.style.thin_hair_aa, "thin-hair AA"),
            with(&|k| k.style.thin_hair_aa = !own.style.thin_hair_aa),
        ),
        match own.style.raster {
            Raster::Hardware => (
                "strands drawn in compute".to_string(),
                with(&|k| k.style.raster = Raster::Compute),
            ),
            Raster::Compute => (
                "strands drawn by the fixed-function rasteriser".to_string(),
                with(&|k| k.style.raster = Raster::Hardware),
            ),
        },
    ];
    debug_assert_eq!(looks.len(), LOOKS);
    looks
}
