//! Pictures from inside the cave of a run, taken in the viewer (docs/viewer.md, "From inside"):
//! a vadose canyon with speleothems, a phreatic tube and a breakdown chamber. The viewpoints
//! are chosen from the run's survey (stations with their passage type and zone) and the rock
//! pieces of its sdf.bin (`passage_detail = "full"`), each checked to look down open passage;
//! the viewer stands at each (`#from=x,y,z&to=x,y,z`) in headless Chromium
//! (`tests/browser.mjs shot`).
//!
//! ```sh
//! cargo run --release -p karst-view --example inside -- out/default [--out docs/images]
//! ```
//!
//! Writes OUT/inside-canyon.png, inside-tube.png and inside-breakdown.png and prints each
//! viewpoint. Needs Debian's chromium and tools/node/node_modules (`cargo xtask test` installs
//! both).

use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};

use glam::DVec3;
use karst_artifact::{StageId, read_artifact};
use karst_sdf::detail::rock::PieceKind;
use karst_sdf::{CarvedTerrain, SdfModel};
use karst_skeleton::{ConduitType, Zone};
use karst_survey::{Station, Survey};
use karst_view::{Server, write_view};

/// A place to stand and the point to look at, skeleton coordinates.
struct Viewpoint {
    name: &'static str,
    from: DVec3,
    to: DVec3,
    what: String,
    /// Layers hidden besides the network's lines (the water, when standing in it).
    hidden: &'static str,
}

fn main() -> ExitCode {
    let mut args = std::env::args().skip(1);
    let (mut run, mut out) = (None, PathBuf::from("docs/images"));
    while let Some(arg) = args.next() {
        match (arg.as_str(), run.is_none()) {
            ("--out", _) => out = args.next().map(PathBuf::from).unwrap_or(out),
            (_, true) => run = Some(PathBuf::from(arg)),
            _ => {
                eprintln!("usage: inside RUN_DIR [--out DIR]");
                return ExitCode::from(2);
            }
        }
    }
    let Some(run) = run else {
        eprintln!("usage: inside RUN_DIR [--out DIR]");
        return ExitCode::from(2);
    };
    match pictures(&run, &out) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(1)
        }
    }
}

fn pictures(run: &Path, out: &Path) -> Result<(), String> {
    let (_, survey) =
        read_artifact::<Survey>(&run.join(StageId::Survey.file_name())).map_err(|e| e.to_string())?;
    let (_, model) =
        read_artifact::<SdfModel>(&run.join(StageId::Sdf.file_name())).map_err(|e| e.to_string())?;
    let pieces: Vec<(PieceKind, DVec3)> = model.full.pieces().iter().map(|p| (p.kind, p.centre())).collect();
    let field = CarvedTerrain::new(model);
    let open = |a: DVec3, b: DVec3| sight(&field, a, b);
    let legs = legs(&survey.stations);
    let viewpoints =
        [canyon(&legs, &pieces, &open), tube(&legs, &open), breakdown(&survey.stations, &pieces, &open)];
    let report = write_view(run, None).map_err(|e| e.to_string())?;
    let server = Server::bind(&report.dir, 0).map_err(|e| e.to_string())?;
    let url = server.url();
    std::thread::spawn(move || server.run());
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    for v in viewpoints.into_iter().flatten() {
        let png = out.join(format!("inside-{}.png", v.name));
        let [f, t] = [v.from, v.to].map(|p| format!("{:.2},{:.2},{:.2}", p.x, p.y, p.z));
        shoot(&format!("{url}#from={f}&to={t}"), &png, v.hidden)?;
        println!("{}: {} (from {f} to {t})", png.display(), v.what);
    }
    Ok(())
}

/// Whether the straight line from `a` to `b` stays in open cave (every 0.25 m).
fn sight(field: &CarvedTerrain, a: DVec3, b: DVec3) -> bool {
    let steps = ((b - a).length() / 0.25).ceil().max(1.0) as usize;
    (0..=steps).all(|k| field.cave(a.lerp(b, k as f64 / steps as f64)) < 0.0)
}

/// Consecutive measured stations of one conduit, 8 m apart (two survey legs), away from
/// junctions and shafts: a station and the one to look at.
fn legs(stations: &[Station]) -> Vec<(&Station, &Station)> {
    let counted = |s: &Station| !s.shaft && !s.junction && s.width > 0.0 && s.height > 0.0;
    stations
        .windows(3)
        .filter(|w| w[0].conduit == w[2].conduit && w[2].station == w[0].station + 2)
        .filter(|w| w.iter().all(counted))
        .map(|w| (&w[0], &w[2]))
        .collect()
}

fn position(s: &Station) -> DVec3 {
    DVec3::from_array(s.position)
}

const SPELEOTHEMS: [PieceKind; 4] =
    [PieceKind::Stalactite, PieceKind::Stalagmite, PieceKind::Column, PieceKind::Flowstone];

/// The air-filled canyon or keyhole leg with the most speleothems within 8 m of the point
/// looked at.
fn canyon(
    legs: &[(&Station, &Station)],
    pieces: &[(PieceKind, DVec3)],
    open: &impl Fn(DVec3, DVec3) -> bool,
) -> Option<Viewpoint> {
    let near =
        |p: DVec3| pieces.iter().filter(|(k, c)| SPELEOTHEMS.contains(k) && c.distance(p) < 8.0).count();
    let (count, (a, b)) = legs
        .iter()
        .filter(|(a, _)| {
            a.zone == Zone::Vadose && matches!(a.kind, ConduitType::Canyon | ConduitType::Keyhole)
        })
        .filter(|(a, b)| open(position(a), position(b)))
        .map(|&(a, b)| (near(position(b)), (a, b)))
        .max_by_key(|(count, (a, _))| (*count, std::cmp::Reverse((a.conduit, a.station))))?;
    Some(Viewpoint {
        name: "canyon",
        from: position(a),
        to: position(b),
        what: format!("vadose {} of conduit {}, {count} speleothems within 8 m", a.kind.name(), a.conduit),
        hidden: "",
    })
}

/// A tube or bedding-plane leg of the common size (its area nearest the median of those legs'
/// areas), air-filled (a relict phreatic passage above today's water table) when there is
/// one: under the water table the camera would stand in the water.
fn tube(legs: &[(&Station, &Station)], open: &impl Fn(DVec3, DVec3) -> bool) -> Option<Viewpoint> {
    let phreatic_shape = |s: &Station| matches!(s.kind, ConduitType::Tube | ConduitType::Bed);
    let candidates: Vec<_> = legs
        .iter()
        .filter(|(a, b)| phreatic_shape(a) && phreatic_shape(b))
        .filter(|(a, b)| open(position(a), position(b)))
        .collect();
    let dry: Vec<_> =
        candidates.iter().filter(|(a, b)| a.zone == Zone::Vadose && b.zone == Zone::Vadose).collect();
    let pool = if dry.is_empty() { candidates.iter().collect() } else { dry };
    let mut areas: Vec<f64> = pool.iter().map(|(a, _)| a.area).collect();
    areas.sort_by(f64::total_cmp);
    let median = *areas.get(areas.len() / 2)?;
    let (a, b) =
        **pool.iter().min_by(|(a, _), (b, _)| (a.area - median).abs().total_cmp(&(b.area - median).abs()))?;
    let flooded = a.zone == Zone::Phreatic;
    Some(Viewpoint {
        name: "tube",
        from: position(a),
        to: position(b),
        what: format!(
            "{} {} of conduit {}, {:.1} × {:.1} m",
            if flooded { "water-filled (water hidden)" } else { "relict phreatic" },
            a.kind.name(),
            a.conduit,
            a.width,
            a.height
        ),
        hidden: if flooded { "water" } else { "" },
    })
}

/// The breakdown chamber with the most blocks, seen from the station 10–35 m from its centre
/// (nearest 20 m) with an open line of sight to it.
fn breakdown(
    stations: &[Station],
    pieces: &[(PieceKind, DVec3)],
    open: &impl Fn(DVec3, DVec3) -> bool,
) -> Option<Viewpoint> {
    let blocks: Vec<DVec3> = pieces.iter().filter(|(k, _)| *k == PieceKind::Block).map(|(_, c)| *c).collect();
    let pile = |c: DVec3| blocks.iter().filter(|b| b.distance(c) < 10.0).copied().collect::<Vec<_>>();
    let densest = blocks.iter().copied().max_by_key(|&c| pile(c).len())?;
    let around = pile(densest);
    let centre = around.iter().sum::<DVec3>() / around.len() as f64;
    // Look at the pile's top: a point two metres over the blocks' centre.
    let target = centre + 2.0 * DVec3::Z;
    let from = stations
        .iter()
        .map(position)
        .filter(|p| (10.0..35.0).contains(&p.distance(target)) && open(*p, target))
        .min_by(|a, b| (a.distance(target) - 20.0).abs().total_cmp(&(b.distance(target) - 20.0).abs()))?;
    Some(Viewpoint {
        name: "breakdown",
        from,
        to: target,
        what: format!("breakdown chamber, {} blocks within 10 m", around.len()),
        hidden: "",
    })
}

/// Opens `url` in headless Chromium and writes the settled picture to `png`.
fn shoot(url: &str, png: &Path, hidden: &str) -> Result<(), String> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let modules = std::env::var_os("KARSTGEN_NODE_MODULES")
        .map(PathBuf::from)
        .unwrap_or_else(|| root.join("../../tools/node/node_modules"));
    let output = Command::new("node")
        .arg(root.join("tests/browser.mjs"))
        .args(["shot", url])
        .arg(png)
        .arg(hidden)
        .env("KARSTGEN_NODE_MODULES", modules)
        .output()
        .map_err(|e| format!("node: {e}"))?;
    if !output.status.success() {
        return Err(format!("browser.mjs shot: {}", String::from_utf8_lossy(&output.stderr)));
    }
    Ok(())
}
