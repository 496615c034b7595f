//! CSV tables (spreadsheets, pandas, GIS; `karst-metrics --csv nodes.csv segments.csv` reads
//! the first two back): `nodes.csv`, `segments.csv` (ids 1-based; categories by name) and
//! `metrics.csv` (karstnet's statistics beside their real-cave range), and the surface streams
//! as `stream_nodes.csv` and `stream_segments.csv` (ids 1-based, flows in m³/s, Table 1's
//! rendering attributes empty where the type has none), comma-delimited, world coordinates in
//! metres. Segment `from,to` follow the water (conduit order when dry).

use karst_metrics::MetricsReport;
use karst_scene::params::ExportFormat;
use karst_skeleton::Zone;
use karst_streams::Streams;

use crate::ExportError;
use crate::folder::Folder;
use crate::frame::Frame;
use crate::network::NetworkView;
use crate::surface::{motion_name, role_name};

/// A CSV field: quoted when it holds a delimiter or a quote.
fn field(text: &str) -> String {
    if text.contains([',', '"', '\n']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}

/// `nodes.csv`, `segments.csv` and `metrics.csv`.
pub fn write(
    folder: &mut Folder,
    frame: &Frame,
    net: &NetworkView,
    metrics: &MetricsReport,
) -> Result<(), ExportError> {
    folder.write("nodes.csv", ExportFormat::Csv, |w| {
        writeln!(w, "id,x,y,z,kind,zone,radius,degree,role,inflow,keypoint")?;
        for (i, n) in net.nodes.iter().enumerate() {
            let [x, y, z] = frame.world(n.position);
            let zone = if n.zone == Zone::Vadose { "vadose" } else { "phreatic" };
            let role = serde_json::to_value(n.role)
                .ok()
                .and_then(|v| v.as_str().map(String::from))
                .unwrap_or_default();
            let keypoint = n.keypoint.as_deref().map(field).unwrap_or_default();
            writeln!(
                w,
                "{},{x},{y},{z},{},{zone},{},{},{role},{},{keypoint}",
                i + 1,
                n.kind.name(),
                n.radius,
                n.degree,
                n.inflow
            )?;
        }
        Ok(())
    })?;
    folder.write("segments.csv", ExportFormat::Csv, |w| {
        writeln!(w, "id,from,to,conduit,type,water,zone,phase,wet,flow,discharge,depth,strahler,branch,length,radius_from,radius_to")?;
        for s in &net.segments {
            let [from, to] = s.flow_ends();
            let radius = if [from, to] == s.nodes { s.radius } else { [s.radius[1], s.radius[0]] };
            writeln!(
                w,
                "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
                s.id,
                from + 1,
                to + 1,
                s.conduit,
                s.conduit_type.name(),
                s.water.name(),
                s.zone.name(),
                s.phase,
                u8::from(s.wet),
                s.flow,
                s.discharge,
                s.depth,
                s.strahler,
                s.branch,
                s.length,
                radius[0],
                radius[1]
            )?;
        }
        Ok(())
    })?;
    folder.write("metrics.csv", ExportFormat::Csv, |w| {
        writeln!(w, "metric,value,real_caves_min,real_caves_max,inside")?;
        for (name, c) in &metrics.karstnet {
            let r = &c.real_caves;
            writeln!(w, "{},{},{},{},{}", field(name), c.value, r.min, r.max, c.inside)?;
        }
        Ok(())
    })
}

/// `stream_nodes.csv` and `stream_segments.csv`: the surface streams.
pub fn write_streams(folder: &mut Folder, frame: &Frame, streams: &Streams) -> Result<(), ExportError> {
    folder.write("stream_nodes.csv", ExportFormat::Csv, |w| {
        writeln!(w, "id,x,y,z,role,source,lateral,inflow")?;
        for (i, n) in streams.nodes.iter().enumerate() {
            let [x, y, z] = frame.world(n.position);
            writeln!(
                w,
                "{},{x},{y},{z},{},{},{},{}",
                i + 1,
                role_name(n.role),
                n.source,
                n.lateral,
                n.inflow
            )?;
        }
        Ok(())
    })?;
    folder.write("stream_segments.csv", ExportFormat::Csv, |w| {
        writeln!(
            w,
            "id,from,to,motion,curve,water,flow,flow_units,slope,speed,width,depth,length,drop,throw,foam,rocks,disturbance,particles"
        )?;
        for (i, s) in streams.segments.iter().enumerate() {
            let curve = s.curve.as_deref().map(field).unwrap_or_default();
            let fall = s.fall.as_ref().map_or([String::new(), String::new()], |f| {
                [f.drop.to_string(), f.throw.to_string()]
            });
            let look = s.look.as_ref().map_or([const { String::new() }; 4], |l| {
                [l.foam, l.rocks, l.disturbance, l.particles].map(|v| v.to_string())
            });
            writeln!(
                w,
                "{},{},{},{},{curve},{},{},{},{},{},{},{},{},{},{}",
                i + 1,
                s.from + 1,
                s.to + 1,
                motion_name(s.motion),
                s.water.name(),
                s.flow,
                s.flow_units,
                s.slope,
                s.speed,
                s.width,
                s.depth,
                streams.length(s),
                fall.join(","),
                look.join(",")
            )?;
        }
        Ok(())
    })
}
