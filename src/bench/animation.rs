//! Skinned, animated bodies (the built-in critter): what skinning costs per vertex, the
//! whole frame of the walking creature against the same creature standing still, and
//! each way of keeping hair out of the deforming body: its update and sampling cost,
//! its device memory and how deep hair still gets under the walk (exact distances to
//! the posed mesh), with collision off for scale.

use std::fmt::Write as _;
use std::sync::Arc;
use std::time::Instant;

use glam::Vec3;

use super::sim::SimRun;
use super::Bench;
use fur_core::scene::{critter, Mesh, Rig, Strands};
use fur_core::scene_file::SceneOptions;
use fur_core::sim::{Sdf, SimParams};
use fur_core::skinning::{self, Playback, SkinnedBody};
use fur_gpu::error::Result;
use fur_gpu::session::{FurSession, SessionSetup};
use fur_gpu::sim::{GpuSim, SkinnedMotion};
use fur_gpu::strand_textures::StrandTextures;

/// Progress ticks: the skinning cost, the walking frame, and each way of collision.
pub(super) fn tasks() -> u64 {
    2 + WAYS.len() as u64
}

/// The walk clip of `rig`, on the spot.
fn walk(rig: &Rig) -> Playback {
    Playback {
        clip: rig.clip_index("walk").ok(),
        ..Default::default()
    }
}

/// The critter with the session's groom (combed along the bones).
fn critter_strands() -> Result<(Mesh, Rig, Strands)> {
    let (mesh, rig) = critter();
    let (mut groom, _) = SceneOptions::default().resolve(&mesh)?;
    groom.comb_field = Some(skinning::fur_flow(&rig));
    let strands = Strands::grow(&mesh, &groom)?;
    Ok((mesh, rig, strands))
}

/// A way to collide with the deforming body.
struct Way {
    name: &'static str,
    capsules: bool,
    collision: bool,
    /// The field's cells along the longest axis, as a multiple of the default's.
    cells: u32,
    /// Carry vertices back through the skin's blend of bones ([`SimParams::skin_blend`]).
    skin_blend: bool,
}

const WAYS: [Way; 5] = [
    Way {
        name: "rest field carried by each root pose + bone capsules, the hair's first eighth by \
               its root's bone and its outer eighth through the skin's blend of bones (default)",
        capsules: true,
        collision: true,
        cells: 1,
        skin_blend: true,
    },
    Way {
        name: "the same without the skin's blend (`--skin-blend off`)",
        capsules: true,
        collision: true,
        cells: 1,
        skin_blend: false,
    },
    Way {
        name: "the same without the skin's blend, with twice the field's cells",
        capsules: true,
        collision: true,
        cells: 2,
        skin_blend: false,
    },
    Way {
        name: "rest field carried by each root pose alone",
        capsules: false,
        collision: true,
        cells: 1,
        skin_blend: false,
    },
    Way {
        name: "collision off",
        capsules: false,
        collision: false,
        cells: 1,
        skin_blend: false,
    },
];

impl Bench<'_> {
    /// (mean, max) depth of strand vertices of `strands` inside the posed critter
    /// (`mesh` skinned as `body`, its field `field`) over the second half of a walk
    /// cycle, colliding the `way` says, fractions of the hair length, from exact
    /// distances.
    fn walk_penetration(
        &self,
        mesh: &Mesh,
        strands: &Strands,
        body: &Arc<SkinnedBody>,
        field: &Sdf,
        way: &Way,
    ) -> Result<(f64, f64)> {
        let playback = walk(&body.rig);
        let params = SimParams {
            collision: way.collision,
            skin_blend: Some(way.skin_blend),
            ..fur_core::scene_file::Scene::default_sim()
        };
        let mut textures = StrandTextures::new(self.device, strands, glam::Mat4::IDENTITY)?;
        let mut gpu = GpuSim::build(
            self.device,
            &textures,
            params,
            1,
            Some(field),
            Some(SkinnedMotion {
                body: body.clone(),
                playback: playback.clone(),
            }),
        )?;
        let v = strands.vertices_per_strand as usize;
        let (samples, every) = if self.quick { (2, 15) } else { (6, 5) };
        gpu.run_frames(&mut textures, 30, |_| glam::DMat4::IDENTITY)?;
        let mut depths = super::metrics::Depths::default();
        for _ in 0..samples {
            fur_core::interrupt::check()?;
            gpu.run_frames(&mut textures, every, |_| glam::DMat4::IDENTITY)?;
            let posed = skinning::cpu::pose(body, &playback.joint_matrices(&body.rig, gpu.time));
            let surface = Mesh {
                positions: posed.positions,
                ..mesh.clone()
            };
            let points: Vec<Vec3> = textures
                .read_positions(textures.current)?
                .into_iter()
                .enumerate()
                .filter(|(i, _)| i % v != 0)
                .map(|(_, p)| p)
                .collect();
            depths.add(&surface, &points);
        }
        Ok(depths.relative_to(f64::from(strands.hair_length())))
    }

    /// Linear blend against dual-quaternion skinning over each clip (60 poses a second,
    /// on the CPU): how far the two put the skin apart and how far they turn its normals,
    /// the roots' frames. This decides whether the device needs the second method.
    fn skinning_methods(&mut self, rig: &Rig, hair_length: f32) {
        let _ = writeln!(
            self.md,
            "**Linear blend against dual-quaternion skinning** (CPU, every vertex at 60 poses \
             a second over each clip): how far apart the two put the skin, in hair lengths, \
             and how far they turn the normals (the roots' frames).\n\n\
             | clip | mean offset | max offset | max normal angle |\n\
             | --- | --- | --- | --- |"
        );
        for (c, clip) in rig.clips.iter().enumerate() {
            let playback = Playback {
                clip: Some(c),
                ..Default::default()
            };
            let poses = (clip.duration() * 60.0).ceil().max(1.0) as usize;
            let (mut max, mut sum, mut count, mut angle) = (0.0f64, 0.0f64, 0usize, 0.0f64);
            for k in 0..poses {
                let m = playback.joint_matrices(rig, k as f64 / 60.0);
                let (lp, ln, _) = rig.skin(&m, &[]);
                let (dp, dn) = skinning::dual_quaternion::skin(rig, &m);
                for ((lp, dp), (ln, dn)) in lp.iter().zip(&dp).zip(ln.iter().zip(&dn)) {
                    let offset = f64::from((*lp - *dp).length() / hair_length);
                    max = max.max(offset);
                    sum += offset;
                    count += 1;
                    let cos = f64::from(ln.dot(*dn)).clamp(-1.0, 1.0);
                    angle = angle.max(cos.acos().to_degrees());
                }
            }
            let mean = sum / count.max(1) as f64;
            let case = format!("LBS vs DQS: {}", clip.name);
            for (metric, value, unit) in [
                ("mean_offset", mean, "fraction of hair length"),
                ("max_offset", max, "fraction of hair length"),
                ("max_normal_degrees", angle, "°"),
            ] {
                self.row("animation", case.clone(), metric, value, unit);
            }
            let _ = writeln!(
                self.md,
                "| {} | {mean:.2e} | {max:.2e} | {angle:.2}° |",
                clip.name
            );
        }
        let _ = writeln!(self.md);
    }

    pub(super) fn animation(&mut self) -> Result<()> {
        let (mesh, rig, strands) = critter_strands()?;
        let body = Arc::new(SkinnedBody::new(&mesh, rig.clone()));
        let playback = walk(&rig);
        let params = fur_core::scene_file::Scene::default_sim();
        let vertices = mesh.vertex_count();

        // Skinning: the integrate-only kernel on the skinned body against the same
        // strands on a rigid one; the difference is the skinning pass and the pose loads.
        let bare = SimParams {
            collision: false,
            ..params.clone()
        };
        let times = self.sims_taking_turns_ms(
            &strands,
            &[
                SimRun {
                    params: bare.clone(),
                    skinned: Some(SkinnedMotion {
                        body: body.clone(),
                        playback: playback.clone(),
                    }),
                    field: None,
                    steps: Some(&[]),
                },
                SimRun {
                    params: bare.clone(),
                    skinned: None,
                    field: None,
                    steps: Some(&[]),
                },
            ],
            |_| glam::DMat4::IDENTITY,
        )?;
        let (skinned_ms, rigid_ms) = (times[0], times[1]);
        let per_vertex_us = (skinned_ms - rigid_ms) * 1e3 / vertices as f64;
        self.row(
            "animation",
            "skinning",
            "ms_per_frame",
            skinned_ms - rigid_ms,
            "ms",
        );
        self.row(
            "animation",
            "skinning",
            "us_per_vertex",
            per_vertex_us,
            "µs",
        );
        (self.progress)("skinning cost");
        let _ = writeln!(
            self.md,
            "## Animation\n\nThe built-in critter ({vertices} vertices, {} bones, {} master hairs of \
             {} vertices), walking on the spot. **Skinning** (the skin pass for every vertex and \
             the root-pose loads), measured as the integrate-only kernel on the skinned body \
             minus the same on a rigid one: {:.3} ms a frame, {per_vertex_us:.3} µs per vertex \
             (wall clock, median).\n",
            rig.joints.len(),
            strands.count(),
            strands.vertices_per_strand,
            skinned_ms - rigid_ms
        );

        self.skinning_methods(&rig, strands.hair_length());

        // The whole frame, walking against standing.
        let frame = |clip: Option<usize>| -> Result<f64> {
            let (groom, settings) = SceneOptions::default().resolve(&mesh)?;
            let mut session = FurSession::new(
                self.device,
                SessionSetup {
                    mesh: mesh.clone(),
                    rig: Some((
                        rig.clone(),
                        Playback {
                            clip,
                            ..playback.clone()
                        },
                    )),
                    groom: &groom,
                    sim: params.clone(),
                    motion: fur_core::sim::Motion::still(),
                    settings,
                    extent: self.frame_extent(),
                    frames_in_flight: 1,
                },
            )?;
            Ok(self.time_frames(&mut session)?.wall)
        };
        let walking = frame(playback.clip)?;
        let standing = frame(None)?;
        self.row("animation", "walking", "wall_ms", walking, "ms");
        self.row("animation", "standing", "wall_ms", standing, "ms");
        self.row(
            "animation",
            "walking / standing",
            "ratio",
            walking / standing,
            "×",
        );
        (self.progress)("walking frame");
        let extent = self.frame_extent();
        let _ = writeln!(
            self.md,
            "**Whole frame** at {}×{} (simulation with collision, both passes, copy to the host; \
             median wall clock): walking {walking:.1} ms, standing still (same body, rest pose) \
             {standing:.1} ms: {:.2}× (target ≤ 1.3×).\n",
            extent.width,
            extent.height,
            walking / standing
        );

        // Collision: each way.
        let (field, _) = Sdf::for_hair(&mesh, &params, strands.hair_length(), true)?;
        let cells = Sdf::cells_for_hair(&mesh, &params, strands.hair_length(), true);
        // Per way: a finer field where it asks for one.
        let mut finer = Vec::new();
        for way in &WAYS {
            let resolution = (cells * way.cells).min(128);
            let fine = (way.cells != 1)
                .then(|| Sdf::build(&mesh, resolution, strands.hair_length()))
                .transpose()?;
            finer.push(fine.map(|(sdf, _)| sdf));
        }
        // Per way: its field and its body (without capsules where the way has none).
        let ways: Vec<(&Way, &Sdf, Arc<SkinnedBody>)> = WAYS
            .iter()
            .zip(&finer)
            .map(|(way, fine)| {
                let mut way_body = SkinnedBody::clone(&body);
                if !way.capsules {
                    way_body.capsules.clear();
                }
                (way, fine.as_ref().unwrap_or(&field), Arc::new(way_body))
            })
            .collect();
        // The step without collision first, then each way with it, taking turns.
        let mut runs = vec![SimRun {
            params: bare.clone(),
            skinned: Some(SkinnedMotion {
                body: body.clone(),
                playback: playback.clone(),
            }),
            field: Some(&field),
            steps: None,
        }];
        for (way, field, way_body) in &ways {
            runs.push(SimRun {
                params: SimParams {
                    collision: way.collision,
                    skin_blend: Some(way.skin_blend),
                    ..params.clone()
                },
                skinned: Some(SkinnedMotion {
                    body: way_body.clone(),
                    playback: playback.clone(),
                }),
                field: Some(*field),
                steps: None,
            });
        }
        let times = self.sims_taking_turns_ms(&strands, &runs, |_| glam::DMat4::IDENTITY)?;
        let no_collision = times[0];
        let _ = writeln!(
            self.md,
            "**Collision with the deforming body.** Each way's update (per substep, on the CPU: \
             posing the capsules), its sampling (the simulation with collision minus without, \
             {no_collision:.3} ms), its device memory, and the depth of strand vertices inside \
             the posed critter over the second half of a walk cycle (exact point-to-mesh \
             distances), as fractions of the hair length (targets: max ≤ {depth}, cost ≤ {cost:.0} % \
             of the simulation step). *Share of the step*: collision's part of the step that \
             includes it; *adds*: what it adds to the step without it.\n\n\
             | way | update µs (CPU) | sampling ms | share of the step | adds | device KiB | mean depth | max depth |\n\
             | --- | --- | --- | --- | --- | --- | --- | --- |",
            depth = super::DEPTH_TARGET,
            cost = 100.0 * super::COLLISION_COST_TARGET,
        );
        for (k, (way, field, way_body)) in ways.iter().enumerate() {
            let start = Instant::now();
            let rounds = 1000;
            for k in 0..rounds {
                let m = playback.joint_matrices(&rig, f64::from(k) / 60.0);
                std::hint::black_box(skinning::capsules::pose(&way_body.capsules, &m));
                if way.skin_blend {
                    std::hint::black_box(skinning::blend::bone_rows(&m, &way_body.rest_inverse));
                }
            }
            let update_us = start.elapsed().as_secs_f64() * 1e6 / f64::from(rounds);
            let with = times[k + 1];
            let sampling = with - no_collision;
            // Collision's part of the step that includes it, and what it adds to the
            // step without it.
            let share = sampling / with;
            let adds = sampling / no_collision;
            let memory = if way.collision {
                let blend = if way.skin_blend {
                    skinning::blend::bytes(field) + rig.joints.len() * 48 * 1024
                } else {
                    0
                };
                (field.bytes() + way_body.capsules.len() * 32 * 1024 + blend) as f64 / 1024.0
            } else {
                0.0
            };
            let (mean, max) = self.walk_penetration(&mesh, &strands, way_body, field, way)?;
            for (metric, value, unit) in [
                ("update_us", update_us, "µs"),
                ("sampling_ms", sampling, "ms"),
                ("step_share", share, "fraction"),
                ("adds_to_step", adds, "fraction"),
                ("device_kib", memory, "KiB"),
                ("mean_penetration", mean, "fraction of hair length"),
                ("max_penetration", max, "fraction of hair length"),
            ] {
                self.row("animation", way.name.to_string(), metric, value, unit);
            }
            let _ = writeln!(
                self.md,
                "| {} | {update_us:.1} | {sampling:.3} | {:.0} % | {:.0} % | {memory:.0} | {mean:.2e} | {max:.2e} |",
                way.name,
                100.0 * share,
                100.0 * adds
            );
            (self.progress)(way.name);
        }
        let _ = writeln!(self.md);
        Ok(())
    }
}
