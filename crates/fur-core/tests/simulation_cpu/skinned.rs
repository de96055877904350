//! Hair on a skinned body: riding along with the root poses, the rigid case, placing.

use super::*;

/// On a skinned body whose strands' root poses turn and travel fast (a third of a radian
/// and 5 cm a frame, with hair 0.4 long), weightless hair at rest rides along with its
/// pose: every vertex stays on its carried rest position (within 1e-5 of the hair
/// length), with no lag from the motion; the poses are asked for at the end of every
/// substep, `n h` after the start, and the simulation's clock says the same.
#[test]
fn resting_hair_rides_along_with_a_moving_skinned_body() {
    let strands = bent_strands();
    let params = SimParams {
        substeps: 3,
        gravity: Vec3::ZERO,
        collision: false,
        ..SimParams::default()
    };
    let h = params.substep_dt();
    let asked = RefCell::new(Vec::new());
    let poses_at = |t: f64| {
        asked.borrow_mut().push(t);
        turning(&strands, t)
    };
    let mut sim = CpuSim::<f64>::new(&strands, params.clone(), DMat4::IDENTITY);
    sim.place(DMat4::IDENTITY, Some(&turning(&strands, 0.0).roots));
    let length = f64::from(strands.hair_length());
    let v = 5;
    let (mut time, mut times) = (0.0f64, Vec::new());
    for frame in 1..=12 {
        sim.step_frame_posed(still, poses_at);
        for _ in 0..params.substeps {
            time += h;
            times.push(time);
        }
        assert_eq!(*asked.borrow(), times, "frame {frame}: the substeps' times");
        assert_eq!(sim.time, time, "frame {frame}: the clock");
        let pose = turning(&strands, time);
        for s in 0..strands.count() {
            let rest = strands.strand(s);
            for i in 0..v {
                let want = carried(&pose.roots[s], rest[0], rest[i]);
                let error = (dvec(sim.current[s * v + i]) - want).length();
                assert!(
                    error <= 1e-5 * length,
                    "frame {frame}, strand {s}, vertex {i}: {error} off its carried rest position"
                );
            }
        }
    }
    // The body really moved: every tip travelled more than half the hair's length.
    for s in 0..strands.count() {
        let travelled =
            (dvec(sim.current[s * v + v - 1]) - strands.strand(s)[4].as_dvec3()).length();
        assert!(
            travelled > 0.5 * length,
            "strand {s}: the tip moved {travelled}"
        );
    }
}

/// A skinned body held at its rest pose (every root pose the identity about its own rest
/// root) simulates exactly as the rigid body does, under gravity and wind, without a
/// placement first (the first posed substep starts from the poses it is given).
#[test]
fn a_skinned_body_held_at_rest_simulates_as_the_rigid_body() {
    let strands = bent_strands();
    let params = SimParams {
        substeps: 2,
        wind: Vec3::new(2.0, 0.0, 1.0),
        collision: false,
        ..SimParams::default()
    };
    let held = posed(held_roots(&strands), Vec::new());
    let mut rigid = CpuSim::<f64>::new(&strands, params.clone(), DMat4::IDENTITY);
    let mut skinned = CpuSim::<f64>::new(&strands, params, DMat4::IDENTITY);
    let length = f64::from(strands.hair_length());
    for frame in 0..20 {
        rigid.step_frame(still);
        skinned.step_frame_posed(still, |_| held.clone());
        for (what, a, b) in [
            ("current", &rigid.current, &skinned.current),
            ("previous", &rigid.previous, &skinned.previous),
        ] {
            for (i, (a, b)) in a.iter().zip(b).enumerate() {
                let error = (*a - *b).length();
                assert!(
                    error <= 1e-12 * length,
                    "frame {frame}, {what} vertex {i}: {error}"
                );
            }
        }
    }
    let fell = (rigid.current[4] - V3::from_vec3(strands.positions[4])).length();
    assert!(fell > 1e-3 * length, "nothing moved ({fell})");
}

/// Placing puts every vertex (root included) of every strand on its rest position
/// carried by its own root pose and then the head transform, not moving; without poses,
/// on its rest position carried by the head transform.
#[test]
fn placing_puts_every_strand_on_its_posed_rest_shape() {
    let strands = bent_strands();
    let mut sim = CpuSim::<f64>::new(&strands, SimParams::default(), DMat4::IDENTITY);
    let head = DMat4::from_rotation_translation(
        glam::DQuat::from_rotation_z(0.4),
        glam::DVec3::new(0.5, -1.0, 2.0),
    );
    // The simulation holds the head transform in f32.
    let head32 = head.as_mat4().as_dmat4();
    let poses: Vec<RootPose> = (0..strands.count())
        .map(|s| RootPose {
            rotation: glam::Mat3::from_axis_angle(Vec3::new(0.0, 0.6, 0.8), 0.5 + 0.7 * s as f32),
            root: Vec3::new(1.0 + s as f32, 2.0, -(s as f32)),
        })
        .collect();
    let v = 5;
    let check = |sim: &CpuSim<f64>, want: &dyn Fn(usize, usize) -> glam::DVec3, what: &str| {
        for s in 0..strands.count() {
            for i in 0..v {
                let at = dvec(sim.current[s * v + i]);
                let error = (at - want(s, i)).length();
                assert!(
                    error < 1e-9,
                    "{what}: strand {s}, vertex {i} off by {error}"
                );
                assert_eq!(
                    sim.previous[s * v + i],
                    sim.current[s * v + i],
                    "{what}: moving"
                );
            }
        }
    };
    sim.place(head, Some(&poses));
    check(
        &sim,
        &|s, i| {
            let rest = strands.strand(s);
            head32.transform_point3(carried(&poses[s], rest[0], rest[i]))
        },
        "posed",
    );
    assert_eq!(sim.last_poses, poses);
    sim.place(head, None);
    check(
        &sim,
        &|s, i| head32.transform_point3(strands.strand(s)[i].as_dvec3()),
        "rigid",
    );
}
