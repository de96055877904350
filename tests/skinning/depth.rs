//! How deep hair gets into the walking critter's skin, with collision and without.

use super::*;

/// Which of the body's rules the walk's simulation runs.
#[derive(Clone, Copy, Debug)]
struct Ways {
    collision: bool,
    /// The skin's blend of bones (else the root's bone alone).
    skin_blend: bool,
}

const EVERY_RULE: Ways = Ways {
    collision: true,
    skin_blend: true,
};

/// When the walk is measured: `samples` times, `every` frames apart, after the first 30.
#[derive(Clone, Copy, Debug)]
struct Sampling {
    samples: usize,
    every: usize,
}

/// Depth of strand vertices inside the posed critter over the second half of a walk
/// cycle (exact point-to-mesh distances), fractions of the longest hair: (mean, max).
fn walk_depths(ways: Ways) -> (f64, f64) {
    walk_depths_at(
        ways,
        Sampling {
            samples: 3,
            every: 10,
        },
    )
}

/// [`walk_depths_with`] at the product's field resolution for a skinned body.
fn walk_depths_at(ways: Ways, frames: Sampling) -> (f64, f64) {
    walk_depths_with(ways, frames, None)
}

/// [`walk_depths`] sampled as `frames` says, the distance field at `cells` along its
/// longest axis (`None`: the product's resolution for a skinned body).
fn walk_depths_with(ways: Ways, frames: Sampling, cells: Option<u32>) -> (f64, f64) {
    let Ways {
        collision,
        skin_blend,
    } = ways;
    let Sampling { samples, every } = frames;
    let device = common::device();
    let (mesh, rig) = critter();
    let (mut groom, _) = fur_core::scene_file::SceneOptions::default()
        .resolve(&mesh)
        .unwrap();
    groom.comb_field = Some(skinning::fur_flow(&rig));
    let strands = Strands::grow(&mesh, &groom).unwrap();
    let body = Arc::new(SkinnedBody::new(&mesh, rig));
    let playback = walk(&body.rig);
    let params = SimParams {
        collision,
        skin_blend: Some(skin_blend),
        sdf_resolution: cells.unwrap_or(0),
        ..fur_core::scene_file::Scene::default_sim()
    };
    let (field, _) =
        fur_core::sim::Sdf::for_hair(&mesh, &params, strands.hair_length(), true).unwrap();
    let mut textures = StrandTextures::new(&device, &strands, glam::Mat4::IDENTITY).unwrap();
    let mut gpu = skinned_sim(
        &device,
        &textures,
        params,
        Some(&field),
        SkinnedMotion {
            body: body.clone(),
            playback: playback.clone(),
        },
    );
    let v = strands.vertices_per_strand as usize;
    let head = |_: f64| DMat4::IDENTITY;
    gpu.run_frames(&mut textures, 30, head).unwrap();
    let (mut sum, mut count, mut max) = (0.0f64, 0usize, 0.0f64);
    for _ in 0..samples {
        gpu.run_frames(&mut textures, every, head).unwrap();
        let posed = skinning::cpu::pose(&body, &playback.joint_matrices(&body.rig, gpu.time));
        let surface = Mesh {
            positions: posed.positions,
            ..mesh.clone()
        };
        let points: Vec<Vec3> = textures
            .read_positions(textures.current)
            .unwrap()
            .into_iter()
            .enumerate()
            .filter(|(i, _)| i % v != 0)
            .map(|(_, p)| p)
            .collect();
        for d in fur_core::sim::sdf::exact_distances(&surface, &points) {
            let depth = f64::from((-d).max(0.0));
            sum += depth;
            count += 1;
            max = max.max(depth);
        }
    }
    drop(gpu);
    drop(textures);
    common::assert_clean(&device);
    let hair = f64::from(strands.hair_length());
    (sum / count as f64 / hair, max / hair)
}

/// Collision keeps the walking critter's hair out of its skin, the deepest vertex within
/// 1 % of the hair length: measured against the same walk without collision. Measured
/// here (3 frames, the default collision with the skin's blend and the root's bone):
/// max 0.95 %, collision dividing the mean depth by 237 and the max by 28; the bounds
/// ask for 5 and 3.2, so a collision doing half its work fails, and so does the previous
/// release's (0.97 % here, but 1.37 % in the benchmark's frames, where the armpit's
/// first vertices show).
#[test]
fn collision_keeps_the_walking_hair_out_of_the_skin() {
    let (mean_on, max_on) = walk_depths(EVERY_RULE);
    let (mean_off, max_off) = walk_depths(Ways {
        collision: false,
        skin_blend: false,
    });
    println!(
        "depth inside the skin, fractions of the hair length: with collision mean {mean_on:.2e} \
         max {max_on:.3}; without mean {mean_off:.2e} max {max_off:.3}"
    );
    assert!(
        mean_off > 1e-4,
        "the walk without collision hardly enters the skin"
    );
    assert!(
        max_on <= fur::bench::DEPTH_TARGET,
        "max depth {max_on} of the hair length"
    );
    assert!(
        mean_on * 5.0 < mean_off,
        "mean depth {mean_on} against {mean_off}"
    );
    assert!(
        max_on * 3.2 < max_off,
        "max depth {max_on} against {max_off}"
    );
}

/// Three rules keep the walking critter's hair out of its skin where the skin folds
/// over (the armpit, as the leg swings back), each bound here on the device: over the
/// benchmark's frames of the walk (six samples five frames apart), the deepest vertex
/// stays within the product's 1 % target with all three (measured 0.98 %), and goes
/// past it with any one taken out:
/// - the root's bone carries the hair's first eighth back (`FUR_TEST_NO_ROOT_BONE` in
///   `collide.glsl` carries it by the root pose, the release before the rule: 1.37 %);
/// - a capsule pushes a vertex no farther from its axis than the root's distance plus
///   the vertex's arc along the hair (`FUR_TEST_NO_REACH` pushes to the capsule's full
///   radius, and a root inside a capsule that overfills its crease has its first
///   vertices pushed into the skin beside it: 1.22 %);
/// - the distance field of a skinned body has twice a rigid body's cells per hair
///   length (`CELLS_PER_HAIR_SKINNED`; at the rigid body's resolution, 32 cells
///   instead of 63 here: 1.73 %).
///
/// The unit test of `Collider::root_bone` and the worked cases of `SimParams::sdf_cells`
/// check those helpers alone, and the reach has no unit test of its own (the CPU twin
/// follows it in the parity tests); parity tests cannot see a rule taken out of both
/// sides alike, so this is where the three bind.
#[test]
fn each_skinned_collision_rule_keeps_the_walking_hair_out() {
    const TARGET_MAX: f64 = fur::bench::DEPTH_TARGET;
    let frames = Sampling {
        samples: 6,
        every: 5,
    };
    let (_, with) = walk_depths_at(EVERY_RULE, frames);
    println!("max depth with every rule, fraction of the hair length: {with:.4}");
    assert!(with <= TARGET_MAX, "max depth {with} with every rule");
    let rigid_cells = {
        let (mesh, _) = critter();
        let strands = Strands::grow(
            &mesh,
            &fur_core::scene_file::SceneOptions::default()
                .resolve(&mesh)
                .unwrap()
                .0,
        )
        .unwrap();
        fur_core::sim::Sdf::cells_for_hair(
            &mesh,
            &fur_core::scene_file::Scene::default_sim(),
            strands.hair_length(),
            false,
        )
    };
    let without = |define: Option<&str>, cells: Option<u32>| match define {
        Some(define) => fur_gpu::gpu::shader::with_test_defines(&[(define, "1")], || {
            walk_depths_with(EVERY_RULE, frames, cells)
        }),
        None => walk_depths_with(EVERY_RULE, frames, cells),
    };
    for (rule, define, cells) in [
        ("the root's bone", Some("FUR_TEST_NO_ROOT_BONE"), None),
        ("the capsules' reach limit", Some("FUR_TEST_NO_REACH"), None),
        (
            "the skinned body's field resolution",
            None,
            Some(rigid_cells),
        ),
    ] {
        let (_, deepest) = without(define, cells);
        println!("max depth without {rule}: {deepest:.4}");
        assert!(
            deepest > TARGET_MAX,
            "max depth {deepest} without {rule}: the rule binds nothing here"
        );
    }
}

/// With the hair's outer eighth carried back through the skin's blend of bones and its
/// first eighth by the root's bone (the default), hair stays farther out of the walking
/// critter than by its root poses alone (`--skin-blend off`): the tips of hair rooted
/// where a paw meets its leg, which the root pose carries with the blend of the two
/// bones while the paw's skin turns with the paw, are no longer the deepest (measured
/// over these frames: max 1.24 % by the root poses, 0.95 % with the skin's blend; mean
/// 5.79e-6 and 4.72e-6).
#[test]
fn the_skins_blend_keeps_hair_out_where_the_skin_bends() {
    // The product's target for the walking critter's deepest vertex (1 % of the hair
    // length, README and docs/benchmark.md), not a figure read off one run; what the
    // skin's blend itself adds is the comparison with the root poses below.
    const TARGET_MAX: f64 = fur::bench::DEPTH_TARGET;
    let (mean_root, max_root) = walk_depths(Ways {
        collision: true,
        skin_blend: false,
    });
    let (mean_blend, max_blend) = walk_depths(EVERY_RULE);
    println!(
        "depth inside the skin, fractions of the hair length: root poses mean \
         {mean_root:.2e} max {max_root:.4}; the skin's blend mean {mean_blend:.2e} max {max_blend:.4}"
    );
    assert!(
        max_blend <= TARGET_MAX,
        "max depth {max_blend} of the hair length"
    );
    assert!(
        max_blend < max_root,
        "max depth {max_blend} against {max_root}"
    );
    assert!(
        mean_blend < mean_root,
        "mean depth {mean_blend} against {mean_root}"
    );
}

/// A still pose under gravity with collision on (the product's defaults, the session's
/// groom): once the hair has settled onto the body, no vertex moves more than 1e-6 of the
/// hair length a frame. Three things make it so (each measured on the CPU twin):
/// - the carried field is sampled trilinearly: the nearest-point sample jumps in the
///   crease between belly and thighs, and ~80 strands hung there in period-2 cycles of
///   0.15 hair lengths a frame;
/// - a bone's capsule counts only as far as it moved relative to a strand's root: at the
///   pose the field was built in, the thigh's capsule and the field's thigh were two
///   shapes of one thigh, and ~14 strands squeezed between them kept creeping by up to
///   1e-2 a frame;
/// - where the field and a capsule both push a vertex, the contact's normal is the
///   whole push's direction (the first one's left the velocity into the other: at held
///   walk poses 3 to 13 strands crept by up to 9e-3 a frame);
/// - slow motion sleeps (1e-3 of a strand's length a frame, with its root still; without
///   it ~85 strands still move by up to 4e-4 a frame at the bind pose).
#[test]
fn a_still_pose_under_gravity_with_collision_comes_to_rest() {
    for skin_blend in [false, true] {
        still_pose_comes_to_rest(SimParams {
            skin_blend: Some(skin_blend),
            ..Default::default()
        });
    }
}

fn still_pose_comes_to_rest(params: SimParams) {
    let device = common::device();
    let (strands, body, sdf) = critter_with_field(&params);
    // The bind pose, and the walk's bent pose at 0.4 s held (legs apart, where the
    // thighs' capsules have moved relative to the belly's roots).
    let held_walk = Playback {
        speed: 0.0,
        start: 0.4,
        ..walk(&body.rig)
    };
    for (what, playback) in [
        ("bind pose", Playback::default()),
        ("walk at 0.4 s", held_walk),
    ] {
        let mut textures = StrandTextures::new(&device, &strands, glam::Mat4::IDENTITY).unwrap();
        let mut gpu = skinned_sim(
            &device,
            &textures,
            params.clone(),
            Some(&sdf),
            SkinnedMotion {
                body: body.clone(),
                playback,
            },
        );
        gpu.run_frames(&mut textures, 300, |_| DMat4::IDENTITY)
            .unwrap();
        let limit = 1e-6 * strands.hair_length();
        let worst = largest_move(&mut gpu, &mut textures, 5);
        println!(
            "{what} (skin's blend {}): largest move a frame after settling: {worst:e} (limit {limit:e})",
            params.blends()
        );
        assert!(
            worst <= limit,
            "{what}: the still pose jitters by {worst} a frame (limit {limit})"
        );
    }
    common::assert_clean(&device);
}

/// The built-in walk never puts one part of the skin inside another (a paw through the
/// other paw on its side): no hair rooted there could be outside both. Points 1 mm under
/// the skin, at 120 poses over the cycle, all read as inside the posed body; where two
/// parts overlap, the ray-cast sign counts two surfaces and reads them as outside.
/// Before the front legs led their diagonal pair by 0.4 rad, 5 to 25 such points showed
/// at 10 % of the cycle (the paws meeting under the body).
#[test]
fn the_walk_keeps_the_skin_out_of_itself() {
    let (mesh, rig) = critter();
    let body = SkinnedBody::new(&mesh, rig);
    let playback = walk(&body.rig);
    let mut worst = (0usize, 0.0f64);
    for k in 0..120 {
        let t = f64::from(k) / 120.0;
        let posed = skinning::cpu::pose(&body, &playback.joint_matrices(&body.rig, t));
        let under: Vec<Vec3> = posed
            .positions
            .iter()
            .zip(&posed.normals)
            .map(|(p, n)| *p - n.normalize() * 1e-3)
            .collect();
        let surface = Mesh {
            positions: posed.positions,
            ..mesh.clone()
        };
        let outside = fur_core::sim::sdf::exact_distances(&surface, &under)
            .iter()
            .filter(|&&d| d > 0.0)
            .count();
        if outside > worst.0 {
            worst = (outside, t);
        }
    }
    assert_eq!(
        worst.0, 0,
        "{} skin points inside another part of the body at t = {}",
        worst.0, worst.1
    );
}
