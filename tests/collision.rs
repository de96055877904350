//! Body collision: the distance field against exact distances, hair kept out of the
//! body on the GPU (lavapipe, validation on), no energy gained at rest, GPU against
//! the CPU reference, and collision rows of the stability matrix.

mod common;

use std::sync::Arc;

use fur::scene::{GroomParams, Mesh, Strands};
use fur::sim::{CpuSim, GpuSim, Motion, MotionKind, Sdf, SimParams, V3};
use fur::strand_textures::StrandTextures;
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

use fur::sim::sdf::exact_distances as exact;

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
                fur::scene::hash_unit(3 * i),
                fur::scene::hash_unit(3 * i + 1),
                fur::scene::hash_unit(3 * i + 2),
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

/// Hair combed down on `mesh`, simulated on the GPU for `frames` frames under strong
/// gravity and a shake; returns the deepest any strand vertex reaches inside the body
/// as a fraction of the hair length, measured with exact distances.
fn deepest(mesh: &Mesh, collision: bool, frames: usize) -> f32 {
    let device = common::device();
    let (_, radius) = mesh.bounds();
    let (groom, params, motion) = fur::sim::sdf::pressing_case(radius, collision);
    let strands = Strands::grow(mesh, &groom).unwrap();
    let hair = strands.hair_length();
    let (sdf, _) = Sdf::build(
        mesh,
        params.sdf_cells(2.0 * radius + 2.0 * hair, hair),
        hair,
    )
    .unwrap();
    let mut textures = StrandTextures::new(&device, &strands, motion.head(0.0).as_mat4()).unwrap();
    let mut gpu = GpuSim::with_body(&device, &textures, params, 1, Some(&sdf)).unwrap();
    assert_eq!(
        gpu.active_steps().contains(&fur::sim::SimStep::Collision),
        collision
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
    let depth = exact(mesh, &model).iter().fold(0.0f32, |d, t| d.max(-t));
    drop(gpu);
    drop(textures);
    common::assert_clean(&device);
    depth / hair
}

#[test]
fn hair_never_passes_through_the_sphere_or_the_blob() {
    for (name, mesh) in [
        ("sphere", Mesh::uv_sphere(2.0, 20, 40)),
        ("blob", Mesh::blob()),
    ] {
        let with = deepest(&mesh, true, 200);
        let without = deepest(&mesh, false, 200);
        println!("{name}: deepest {with} of the hair length with collision, {without} without");
        assert!(
            without > 0.1,
            "{name}: the test does not push hair into the body ({without})"
        );
        assert!(
            with <= 0.01,
            "{name}: hair {with} of its length inside the body"
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

#[test]
fn gpu_collision_matches_the_cpu_reference() {
    let device = common::device();
    let mesh = Mesh::blob();
    let groom = GroomParams {
        segments: 10,
        segment_length: 0.03,
        comb_direction: Vec3::NEG_Y,
        comb_strength: 2.5,
        ..Default::default()
    };
    let strands = Strands::grow(&mesh, &groom).unwrap();
    let hair = strands.hair_length();
    let params = SimParams {
        gravity: Vec3::new(0.0, -30.0, 0.0),
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
    gpu.run_frames(&mut textures, 40, |t| motion.head(t))
        .unwrap();
    for _ in 0..40 {
        cpu.step_frame(|t| motion.head(t));
    }
    let on_gpu = textures.read_positions(textures.current).unwrap();
    let error = on_gpu
        .iter()
        .zip(&cpu.current)
        .map(|(g, c)| (*g - c.to_vec3()).length())
        .fold(0.0f32, f32::max);
    // Collisions happened: vertices sit on the margin.
    let to_model = motion.head(cpu.time).inverse();
    let margin = cpu.params.collision_margin * hair;
    let touching = cpu
        .current
        .iter()
        .filter(|p| {
            let m = to_model.as_mat4().transform_point3(p.to_vec3());
            sdf.sample(V3::<f32>::from_vec3(m))
                .is_some_and(|(d, _)| d < 1.5 * margin)
        })
        .count();
    println!("max |gpu - cpu| {error:e}; {touching} vertices on the margin");
    assert!(touching > 100, "only {touching} vertices collided");
    assert!(error <= 1e-4 * hair, "GPU and CPU differ by {error}");
    drop(gpu);
    drop(textures);
    common::assert_clean(&device);
}
