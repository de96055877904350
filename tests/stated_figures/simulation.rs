//! The phrases docs/simulation.md must hold word for word, each built from the
//! constant it states: the simulation's defaults, the collision's and the skinned
//! critter's.

use super::phrases::count_text;
use fur_core::files::size_text;

/// The simulation page's defaults, limits and counts.
pub fn simulation() -> Vec<(&'static str, Vec<String>)> {
    let scene = fur_core::scene_file::SceneOptions::default();
    let sim = fur_core::sim::params::SimParams::default();
    let frame = format!("1/{}", (1.0 / sim.dt).round());
    let (critter, rig) = fur_core::scene::critter();
    let near = fur_core::sim::collide::NEAR_CAPSULES;
    vec![(
        "docs/simulation.md",
        vec![
            format!("default {frame} s, one substep"),
            format!("four vectors in a {}° cone", sim.wind_cone_deg),
            format!(
                "One invocation per strand, {} strands per workgroup",
                fur_gpu::gpu::shader::GROUP_SIZE
            ),
            format!(
                "moved by at most {} ulps of its largest coordinate",
                fur_core::sim::cpu::SLEEP_ULPS
            ),
            format!(
                "{}–{} cells along the longest axis",
                sim.sdf_cells(1.0, 1e9, false),
                sim.sdf_cells(1e9, 1.0, false)
            ),
            format!(
                "a fraction of each strand's own length, default {})",
                sim.collision_margin
            ),
            format!("`--friction` (default {})", sim.friction),
            format!("(vertices 1 and 2 of {})", scene.segments),
            format!(
                "where its grid would pass {}",
                size_text(fur_core::skinning::blend::MAX_BYTES as u64)
            ),
            format!(
                "({} vertices, closed and outward), {} bones",
                count_text(critter.vertex_count() as u64),
                rig.joints.len()
            ),
            format!(
                "with the {} bone capsules nearest its root",
                ["no", "one", "two", "three", "four", "five", "six"][near.min(6)]
            ),
        ],
    )]
}
