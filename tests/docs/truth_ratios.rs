//! The ratios the README works out from docs/ground-truth.md's run, for the tests of
//! tests/docs.rs that check the README's sentences and figures against them.

use super::{read, region, tables};

/// The ratios the README works out from the truth tables (docs/ground-truth.md's run):
/// Marschner's ꟻLIP over Kajiya–Kay's on the blob, sphere, walking critter and drawn
/// groom, then on
/// white, blond, black and tabby fur, and the range of their frame times' ratio.
pub struct TruthRatios {
    pub scenes: Vec<f64>,
    pub colours: Vec<f64>,
    pub fastest: f64,
    pub slowest: f64,
    /// Kajiya–Kay's ꟻLIP minus Marschner's, in the same order (scenes, then colours).
    pub gaps: Vec<f64>,
}

impl TruthRatios {
    /// The figures as the documents write them: ratios to two places, the frame times'
    /// range to one, the gaps to four.
    pub fn derived(&self) -> Vec<String> {
        let ratios = self.scenes.iter().chain(&self.colours);
        ratios
            .map(|x| format!("{x:.2}"))
            .chain([
                format!("{:.1}", self.fastest),
                format!("{:.1}", self.slowest),
            ])
            .chain(self.gaps.iter().map(|g| format!("{g:.4}")))
            .collect()
    }
}

pub fn truth_ratios() -> TruthRatios {
    let truth = read("docs/ground-truth.md");
    let run = tables(region(&truth, "fur bench"));
    let figure = |row: &[String], header: &[String], name: &str| -> f64 {
        let i = header.iter().position(|h| h == name).unwrap();
        row[i].parse().unwrap()
    };
    // Per scene (blob, sphere, walking critter, drawn groom, in the run's order): the
    // Kajiya–Kay drawing's row and the Marschner drawing's, one of them the scene's
    // default (the original's sphere keeps Kajiya–Kay).
    let mut scenes = Vec::new();
    let mut times = Vec::new();
    let mut gaps = Vec::new();
    for (header, rows) in run.iter().filter(|(h, _)| h[0] == "drawing") {
        let find = |name: &str| rows.iter().find(|r| r[0] == name);
        let pair = match (find("Kajiya–Kay lighting"), find("Marschner lighting")) {
            (Some(kk), None) => Some((kk, find("rung 0 (default)"))),
            (None, Some(m)) => find("rung 0 (default)").map(|kk| (kk, Some(m))),
            _ => None,
        };
        if let Some((kk, Some(m))) = pair {
            scenes.push(figure(m, header, "ꟻLIP") / figure(kk, header, "ꟻLIP"));
            times.push(figure(m, header, "frame ms") / figure(kk, header, "frame ms"));
            gaps.push(figure(kk, header, "ꟻLIP") - figure(m, header, "ꟻLIP"));
        }
    }
    assert_eq!(
        scenes.len(),
        4,
        "the blob, sphere, critter and drawn groom tables"
    );
    let (header, rows) = run
        .iter()
        .find(|(h, _)| h[0] == "fur")
        .expect("the fur colours' table");
    let colour = |fur: &str, drawing: &str| {
        rows.iter()
            .find(|r| r[0] == fur && r[1] == drawing)
            .unwrap_or_else(|| panic!("no {fur} {drawing} row"))
    };
    let mut colours = Vec::new();
    for fur in ["white", "blond", "black", "tabby"] {
        let (kk, m) = (colour(fur, "Kajiya–Kay"), colour(fur, "Marschner"));
        colours.push(figure(m, header, "ꟻLIP") / figure(kk, header, "ꟻLIP"));
        times.push(figure(m, header, "frame ms") / figure(kk, header, "frame ms"));
        gaps.push(figure(kk, header, "ꟻLIP") - figure(m, header, "ꟻLIP"));
    }
    let (fastest, slowest) = times
        .iter()
        .fold((f64::MAX, f64::MIN), |(lo, hi), &t| (lo.min(t), hi.max(t)));
    TruthRatios {
        scenes,
        colours,
        fastest,
        slowest,
        gaps,
    }
}
