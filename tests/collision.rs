//! Body collision: the distance field against exact distances, hair kept out of the
//! body on the GPU (lavapipe, validation on), no energy gained at rest, GPU against
//! the CPU reference, and collision rows of the stability matrix.

mod common;

use std::sync::Arc;

use common::rounding::{self, Body};

use fur_core::scene::{GroomParams, Mesh, Strands};
use fur_core::sim::{CpuSim, Motion, MotionKind, Sdf, SimParams, V3};
use fur_gpu::sim::GpuSim;
use fur_gpu::strand_textures::StrandTextures;
use glam::{DMat4, Vec3};

/// A closed cube of half-size `h` centred on the origin, outward-facing.
fn cube(h: f32) -> Mesh {
    let positions: Vec<Vec3> = (0..8)
        .map(|i| {
            Vec3::new(
                if i & 1 == 0 { -h } else { h },
                if i & 2 == 0 { -h } else { h },
                if i & 4 == 0 { -h } else { h },
            )
        })
        .collect();
    let quads = [
        [0, 2, 3, 1], // -z
        [4, 5, 7, 6], // +z
        [0, 1, 5, 4], // -y
        [2, 6, 7, 3], // +y
        [0, 4, 6, 2], // -x
        [1, 3, 7, 5], // +x
    ];
    let indices = quads
        .iter()
        .flat_map(|q| [q[0], q[1], q[2], q[0], q[2], q[3]])
        .collect();
    let mut mesh = Mesh {
        normals: Vec::new(),
        positions,
        indices,
        uvs: Vec::new(),
        texture: None,
    };
    mesh.normals = mesh.face_weighted_normals();
    mesh
}

use fur_core::sim::sdf::exact_distances as exact;

/// Deterministic points spread over the field's grid.
fn sample_points(sdf: &Sdf, count: usize) -> Vec<Vec3> {
    let extent = Vec3::new(
        (sdf.dims[0] - 1) as f32,
        (sdf.dims[1] - 1) as f32,
        (sdf.dims[2] - 1) as f32,
    ) * sdf.cell;
    (0..count as u32)
        .map(|i| {
            let u = Vec3::new(
                fur_core::scene::hash_unit(3 * i),
                fur_core::scene::hash_unit(3 * i + 1),
                fur_core::scene::hash_unit(3 * i + 2),
            );
            sdf.origin + u * extent
        })
        .collect()
}

#[test]
fn the_distance_field_matches_exact_distances_and_signs() {
    for (name, mesh, analytic) in [
        (
            "sphere",
            Mesh::uv_sphere(2.0, 40, 80),
            Some(Box::new(|p: Vec3| p.length() - 2.0) as Box<dyn Fn(Vec3) -> f32>),
        ),
        (
            "cube",
            cube(1.0),
            Some(Box::new(|p: Vec3| {
                let q = p.abs() - Vec3::ONE;
                q.max(Vec3::ZERO).length() + q.max_element().min(0.0)
            }) as Box<dyn Fn(Vec3) -> f32>),
        ),
        ("blob", Mesh::blob(), None),
    ] {
        let (sdf, report) = Sdf::build(&mesh, 32, 0.4).unwrap();
        assert!(report.closed(), "{name}: {report:?}");
        assert!(report.warning(name).is_none());
        let points = sample_points(&sdf, 3000);
        let truth = exact(&mesh, &points);
        let (mut worst, mut inside, mut outside) = (0.0f32, 0, 0);
        for (p, t) in points.iter().zip(&truth) {
            let (d, _) = sdf.sample(V3::<f32>::from_vec3(*p)).unwrap();
            worst = worst.max((d - t).abs());
            if let Some(f) = &analytic {
                // The mesh is the shape (the sphere up to its facets' sagitta).
                assert!((f(*p) - t).abs() < 4e-3, "{name} at {p}: {t} vs {}", f(*p));
            }
            if t.abs() > sdf.cell {
                assert_eq!(d > 0.0, *t > 0.0, "{name}: wrong sign at {p}: {d} vs {t}");
                if *t > 0.0 {
                    outside += 1;
                } else {
                    inside += 1;
                }
            }
        }
        println!("{name}: cell {}, worst error {worst}", sdf.cell);
        assert!(
            worst <= 0.5 * sdf.cell,
            "{name}: error {worst} over half a cell {}",
            sdf.cell
        );
        assert!(
            inside > 100 && outside > 100,
            "{name}: {inside} in, {outside} out"
        );
    }
}

#[test]
fn an_open_or_inconsistent_mesh_is_named_in_a_warning() {
    // The blob with its top half removed: a bowl.
    let blob = Mesh::blob();
    let mut bowl = blob.clone();
    bowl.indices = blob
        .indices
        .chunks_exact(3)
        .filter(|t| t.iter().all(|&i| blob.positions[i as usize].y < 0.3))
        .flatten()
        .copied()
        .collect();
    let (_, report) = Sdf::build(&bowl, 24, 0.2).unwrap();
    assert!(report.boundary_edges > 0, "{report:?}");
    let warning = report.warning("bowl.obj").expect("a warning");
    assert!(
        warning.contains("bowl.obj") && warning.contains("open edges"),
        "{warning}"
    );
    // One triangle flipped: closed, but inconsistently oriented.
    let mut flipped = blob.clone();
    flipped.indices.swap(0, 1);
    let (_, report) = Sdf::build(&flipped, 24, 0.2).unwrap();
    assert!(
        report.boundary_edges == 0 && report.inconsistent_edges == 3,
        "{report:?}"
    );
    assert!(report.warning("flipped").is_some());
    // A UV sphere's duplicated seam is no hole.
    let (_, report) = Sdf::build(&Mesh::uv_sphere(2.0, 12, 24), 16, 0.2).unwrap();
    assert!(report.closed(), "{report:?}");
}

/// What the pressing case left, as fractions of the hair length.
struct Pressed {
    /// The nearest any strand vertex but a root comes to the body's surface, by exact
    /// distance (negative inside).
    nearest: f64,
    /// The nearest any of them is by the collider's own field, over its margin.
    in_field: f64,
    /// The collision margin.
    margin: f64,
    /// The field's largest error against exact distances within two cells outside the
    /// surface (`common::field_error`).
    field_error: f64,
}

/// Hair combed down on `mesh`, simulated on the GPU for `frames` frames under strong
/// gravity and a shake (`pressing_case`), with the collider keeping `margin` of the hair
/// length out (`None`: collision off).
fn pressed(mesh: &Mesh, margin: Option<f32>, frames: usize) -> Pressed {
    let device = common::device();
    let (_, radius) = mesh.bounds();
    let (groom, params, motion) = fur_core::sim::sdf::pressing_case(radius, margin.is_some());
    let params = SimParams {
        collision_margin: margin.unwrap_or(params.collision_margin),
        ..params
    };
    let strands = Strands::grow(mesh, &groom).unwrap();
    let hair = strands.hair_length();
    let (sdf, _) = Sdf::build(
        mesh,
        params.sdf_cells(2.0 * radius + 2.0 * hair, hair, false),
        hair,
    )
    .unwrap();
    let field_error = common::field_error(mesh, &sdf, (0.0, 2.0 * sdf.cell)) / f64::from(hair);
    let mut textures = StrandTextures::new(&device, &strands, motion.head(0.0).as_mat4()).unwrap();
    let mut gpu = GpuSim::with_body(&device, &textures, params.clone(), 1, Some(&sdf)).unwrap();
    assert_eq!(
        gpu.active_steps()
            .contains(&fur_core::sim::SimStep::Collision),
        margin.is_some()
    );
    gpu.run_frames(&mut textures, frames, |t| motion.head(t))
        .unwrap();
    let world = textures.read_positions(textures.current).unwrap();
    let to_model = motion.head(gpu.time).inverse().as_mat4();
    let v = strands.vertices_per_strand as usize;
    let model: Vec<Vec3> = world
        .iter()
        .enumerate()
        .filter(|(i, _)| i % v != 0) // roots sit on the surface
        .map(|(_, p)| to_model.transform_point3(*p))
        .collect();
    let nearest = exact(mesh, &model).iter().fold(f32::MAX, |d, t| d.min(*t));
    let in_field = model
        .iter()
        .filter_map(|p| sdf.sample(V3::<f32>::from_vec3(*p)))
        .fold(f32::MAX, |d, (f, _)| d.min(f));
    drop(gpu);
    drop(textures);
    common::assert_clean(&device);
    let margin = margin.unwrap_or(0.0);
    Pressed {
        nearest: f64::from(nearest / hair),
        in_field: f64::from(in_field / (margin * hair)),
        margin: f64::from(margin),
        field_error,
    }
}

#[test]
fn hair_never_passes_through_the_sphere_or_the_blob() {
    for (name, mesh) in [
        ("sphere", Mesh::uv_sphere(2.0, 20, 40)),
        ("blob", Mesh::blob()),
    ] {
        let with = pressed(&mesh, Some(0.02), 200);
        let half = pressed(&mesh, Some(0.01), 200);
        let without = pressed(&mesh, None, 200);
        println!(
            "{name}: nearest vertex {:.4} of the hair length out (margin {}, field error \
             {:.4}), {:.3} of the margin by the field; with half the margin {:.4}; without \
             collision {:.2}",
            with.nearest,
            with.margin,
            with.field_error,
            with.in_field,
            half.nearest,
            without.nearest
        );
        // The test pushes hair into the body: without collision, over a hair length deep.
        assert!(
            without.nearest < -1.0,
            "{name}: the test does not push hair into the body ({})",
            without.nearest
        );
        // The collider's contract, in its own field: every vertex at least the margin
        // out. It projects a vertex onto the margin along the field's gradient up to
        // three times; a step that crosses into the next grid point's linear patch can
        // leave it short by the change of the field's slope over the step, which three
        // projections bring under 5 % of the margin (measured: under 0.2 %). A collider
        // keeping half the margin fails it.
        assert!(
            with.in_field >= 0.95,
            "{name}: a vertex is {} of the margin out by the field",
            with.in_field
        );
        assert!(
            half.in_field * 0.5 < 0.95,
            "{name}: half the margin passes the contract"
        );
        // And by exact distances: the field is within its error of the surface, so
        // every vertex is at least 0.95 × margin − error out (on the sphere a real
        // distance outside; the blob's field errs by more than the margin near its
        // sharpest folds, so there only no deeper than that).
        let bound = 0.95 * with.margin - with.field_error;
        assert!(
            with.nearest >= bound,
            "{name}: a vertex {} of the hair length from the surface, under {bound}",
            with.nearest
        );
    }
}

#[test]
fn hair_resting_on_the_body_stays_still() {
    // Hair combed flat over a flat body under gravity, free to droop (no shape
    // constraints): it falls onto the surface, settles, and must then stay put: no
    // energy gained from the contact, no jitter.
    let mesh = Mesh::grid(10, 10, 4.0);
    let groom = GroomParams {
        segments: 10,
        segment_length: 0.05,
        comb_direction: Vec3::X,
        comb_strength: 4.0,
        ..Default::default()
    };
    let strands = Strands::grow(&mesh, &groom).unwrap();
    let hair = strands.hair_length();
    let params = SimParams {
        global_stiffness: 0.0,
        local_stiffness: 0.0,
        ..SimParams::default()
    };
    let (sdf, _) = Sdf::build(&mesh, 64, hair).unwrap();
    let mut sim = CpuSim::<f32>::new(&strands, params, DMat4::IDENTITY).with_sdf(Arc::new(sdf));
    let v = strands.vertices_per_strand as usize;
    // Strands well inside the plane's edges.
    let inner: Vec<usize> = (0..strands.count())
        .filter(|&s| {
            let root = strands.positions[s * v];
            root.x.abs() < 1.0 && root.z.abs() < 1.0
        })
        .collect();
    assert!(inner.len() > 20);
    let speed = |sim: &CpuSim<f32>| {
        inner
            .iter()
            .flat_map(|&s| (1..v).map(move |i| s * v + i))
            .map(|i| f64::from((sim.current[i] - sim.previous[i]).length()))
            .fold(0.0f64, f64::max)
    };
    let mut speeds = Vec::new();
    for _ in 0..500 {
        sim.step_frame(|_| DMat4::IDENTITY);
        speeds.push(speed(&sim) / f64::from(hair));
    }
    let falling = speeds[..20].iter().copied().fold(0.0, f64::max);
    let late = speeds[400..].iter().copied().fold(0.0, f64::max);
    println!("fastest vertex per frame, of the hair length: {falling} falling, {late} at rest");
    assert!(falling > 1e-3, "the hair never fell: {falling}");
    assert!(
        late < 1e-6,
        "still moving (jitter or energy gain) after 400 frames: {late}"
    );
    // Resting on the surface, not sunk into it or floating above.
    let lowest = inner
        .iter()
        .flat_map(|&s| (1..v).map(move |i| s * v + i))
        .map(|i| sim.current[i].1)
        .fold(f32::MAX, f32::min);
    assert!(
        lowest > 0.0 && lowest < 0.05 * hair,
        "lowest vertex at {lowest}"
    );
}

/// The parity budget counts the kernel's operations: checked by hand where it is small.
#[test]
fn the_rounding_budget_is_the_operation_count() {
    rounding::check_the_budget_by_hand();
}

#[test]
fn gpu_collision_matches_the_cpu_reference() {
    let device = common::device();
    let mesh = Mesh::blob();
    // Hair combed down hard, no global shape and a soft local one, under strong
    // gravity: it lies on the body (see `pressing_case`).
    let groom = GroomParams {
        segments: 10,
        segment_length: 0.03,
        comb_direction: Vec3::NEG_Y,
        comb_strength: 3.0,
        flow: fur_core::scene::Flow::Direction,
        ..Default::default()
    };
    let strands = Strands::grow(&mesh, &groom).unwrap();
    let hair = strands.hair_length();
    let params = SimParams {
        gravity: Vec3::new(0.0, -40.0, 0.0),
        global_stiffness: 0.0,
        local_stiffness: 0.3,
        substeps: 2,
        wind: Vec3::new(2.0, 0.0, 1.0),
        ..SimParams::default()
    };
    let motion = Motion {
        kind: MotionKind::Nod,
        amplitude: 25.0,
        rate: 1.5,
    };
    let (sdf, _) = Sdf::build(&mesh, 40, hair).unwrap();
    let sdf = Arc::new(sdf);
    let mut textures = StrandTextures::new(&device, &strands, motion.head(0.0).as_mat4()).unwrap();
    let mut gpu = GpuSim::with_body(&device, &textures, params.clone(), 1, Some(&sdf)).unwrap();
    let mut cpu = CpuSim::<f32>::new(&strands, params, motion.head(0.0)).with_sdf(sdf.clone());
    // Frame by frame from the same state: the CPU takes the GPU's positions and previous
    // positions before each frame, so what is compared is one frame's arithmetic, with
    // thousands of vertices in contact. Left to run apart, the two part within a few
    // frames wherever a vertex sits within a rounding of the margin: one side counts a
    // contact and takes the normal velocity and friction off it, the other does not,
    // and the difference grows as any contact's does. Within one frame such a flip in
    // its first substep changes what the second carries by at most the vertex's velocity
    // (the projection itself is continuous at the margin), so: every vertex within the
    // frame's rounding budget (tests/common/rounding.rs: derived from the precision
    // Vulkan allows, not from one driver's result), but for the contacts decided apart,
    // which must each be a contact (within two margins of the body), within the budget
    // plus their step, and at most 1 % of the vertices in contact (contacts decided apart
    // sit within a rounding of the margin; a collision step that differs for every
    // contact fails).
    let v = strands.vertices_per_strand as usize;
    let margin = cpu.params.collision_margin * hair;
    let in_contact = |sim: &CpuSim<f32>, i: usize| {
        let m = motion
            .head(sim.time)
            .inverse()
            .as_mat4()
            .transform_point3(sim.current[i].to_vec3());
        sdf.sample(V3::<f32>::from_vec3(m))
            .is_some_and(|(d, _)| d < 2.0 * margin)
    };
    let mut error = 0.0f32;
    let mut flips = 0;
    let mut worst_budget = 0.0f32;
    for frame in 0..40 {
        common::take_device_state(&mut cpu, &textures);
        gpu.run_frames(&mut textures, 1, |t| motion.head(t))
            .unwrap();
        cpu.step_frame(|t| motion.head(t));
        assert_eq!(cpu.time, gpu.time);
        let on_gpu = textures.read_positions(textures.current).unwrap();
        let before = textures.read_positions(1 - textures.current).unwrap();
        let tolerance = rounding::frame_budget(
            &cpu.params,
            Body::Rigid,
            v as u32,
            rounding::reach(&on_gpu),
            groom.segment_length,
        );
        worst_budget = worst_budget.max(tolerance);
        let contacts = (0..on_gpu.len())
            .filter(|&i| i % v != 0 && in_contact(&cpu, i))
            .count();
        let mut over = 0;
        for (i, ((g, c), p)) in on_gpu.iter().zip(&cpu.current).zip(&before).enumerate() {
            let off = (*g - c.to_vec3()).length();
            if off > tolerance {
                over += 1;
                let step = (*g - *p).length();
                assert!(
                    off <= tolerance + step,
                    "frame {frame}: vertex {i} {off:e} off, more than its step {step:e}"
                );
                assert!(
                    in_contact(&cpu, i),
                    "frame {frame}: vertex {i} {off:e} off (budget {tolerance:e}) is no contact"
                );
            } else {
                error = error.max(off);
            }
        }
        assert!(
            100 * over <= contacts,
            "frame {frame}: {over} vertices differ by more than {tolerance:e}, of {contacts} in contact"
        );
        flips += over;
    }
    // Collisions happened: strand vertices (not the roots, which sit on the surface by
    // construction) rest on the margin.
    let to_model = motion.head(cpu.time).inverse();
    let touching = cpu
        .current
        .iter()
        .enumerate()
        .filter(|(i, p)| {
            let m = to_model.as_mat4().transform_point3(p.to_vec3());
            i % v != 0
                && sdf
                    .sample(V3::<f32>::from_vec3(m))
                    .is_some_and(|(d, _)| d < 1.5 * margin)
        })
        .count();
    println!(
        "max |gpu - cpu| over a frame {error:e} (budget up to {worst_budget:e}) but for \
         {flips} contacts decided apart; {touching} strand vertices (not roots) on the margin"
    );
    assert!(touching > 1000, "only {touching} strand vertices collided");
    drop(gpu);
    drop(textures);
    common::assert_clean(&device);
}
