//! Laying the fur's flow (docs/design.md, "How grown fur lies"): on models from the
//! blob's 2,562 vertices to a 100K-vertex sphere, the time to build the flow field (the
//! heat method's two sparse solves) and to grow the master hairs along it as the
//! default scene does (the field, the half-thickness and the hairs), and where the
//! field turns: its singular points and their index sum.

use std::fmt::Write as _;
use std::time::Instant;

use super::metrics::median;
use super::Bench;
use fur_core::scene::{FlowField, FlowFrom, Mesh, Strands};
use fur_core::scene_file::SceneOptions;
use fur_gpu::error::Result;

/// The models, smallest first; the quick suite takes the first two.
fn models(quick: bool) -> Vec<(&'static str, Mesh)> {
    let mut all = vec![
        ("blob", Mesh::blob()),
        ("critter (as a rigid body)", fur_core::scene::critter().0),
    ];
    if !quick {
        all.push(("icosphere, 6 subdivisions", Mesh::icosphere(6)));
        all.push(("UV sphere, 250 × 400", Mesh::uv_sphere(1.0, 250, 400)));
    }
    all
}

pub(super) fn tasks(quick: bool) -> u64 {
    models(quick).len() as u64
}

impl Bench<'_> {
    pub(super) fn flow(&mut self) -> Result<()> {
        let reps = if self.quick { 1 } else { 3 };
        let _ = writeln!(
            self.md,
            "## Laying the flow\n\nThe flow field built from the head end `auto` chooses \
             (the heat method: its two sparse factorisations and solves, the gradients), and \
             the master hairs grown along it as the default scene grows them (the field, the \
             model's half-thickness for the thickness limit and the thin parts, the hairs), \
             on one thread; median of {reps}. Singular points: where the field turns, and \
             their indices' sum (2 on a closed body).\n\n\
             | model | vertices | field s | grown s | singular points | index sum |\n\
             | --- | --- | --- | --- | --- | --- |"
        );
        for (name, mesh) in models(self.quick) {
            let (groom, _) = SceneOptions::default().resolve(&mesh)?;
            let mut field_s = Vec::new();
            let mut grow_s = Vec::new();
            let mut field = None;
            for _ in 0..reps {
                let started = Instant::now();
                field = Some(FlowField::build(&mesh, FlowFrom::Auto)?);
                field_s.push(started.elapsed().as_secs_f64());
                let started = Instant::now();
                Strands::grow(&mesh, &groom)?;
                grow_s.push(started.elapsed().as_secs_f64());
            }
            let points = field.map_or_else(Vec::new, |f| f.singular_points(&mesh));
            let sum: i32 = points.iter().map(|p| p.index).sum();
            let (field_s, grow_s) = (median(&field_s), median(&grow_s));
            self.row("flow", name, "field_s", field_s, "s");
            self.row("flow", name, "grow_s", grow_s, "s");
            self.row("flow", name, "singular_points", points.len() as f64, "");
            self.row("flow", name, "index_sum", f64::from(sum), "");
            let _ = writeln!(
                self.md,
                "| {name} | {} | {field_s:.3} | {grow_s:.3} | {} | {sum} |",
                super::grooms::grouped(mesh.vertex_count()),
                points.len()
            );
            (self.progress)(name);
        }
        self.md.push('\n');
        Ok(())
    }
}
