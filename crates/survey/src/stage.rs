//! The survey stage's contract: `skeleton.json` and `sdf.bin` in, `survey.json` and
//! `passages.csv` out.

use std::io::Write;
use std::path::Path;

use karst_artifact::{Header, StageId};
use karst_sdf::SdfModel;
use karst_skeleton::Skeleton;
use karst_stage::Stage;

use crate::build::{build, zone_name};
use crate::error::SurveyError;
use crate::payload::Survey;
use crate::view::SurveyView;

/// Stage 8: the passages measured as a survey would.
pub struct SurveyStage;

impl Stage for SurveyStage {
    const ID: StageId = StageId::Survey;
    type Inputs = (Skeleton, SdfModel);
    type Output = Survey;
    type Error = SurveyError;
    type View<'s> = SurveyView<'s>;

    fn build(_: &SurveyView, (skeleton, model): &(Skeleton, SdfModel)) -> Result<Survey, SurveyError> {
        build(skeleton, model)
    }

    fn headline(_: &SurveyView, survey: &Survey) -> String {
        let inside = survey.statistics.values().filter(|s| s.inside).count();
        format!(
            "{} stations ({} counted), {inside}/{} passage statistics within real caves, {:.0} m³ of void",
            survey.stations.len(),
            survey.counted,
            survey.statistics.len(),
            survey.void_volume.total
        )
    }

    fn summary(_: &Header, survey: &Survey) -> Vec<String> {
        let mut lines = vec![format!(
            "{} stations every {} m, {} counted (not shafts, not at junctions)",
            survey.stations.len(),
            survey.spacing,
            survey.counted
        )];
        for (name, s) in &survey.statistics {
            let verdict = if s.inside { "inside" } else { "OUTSIDE" };
            let value = s.value.map_or("undefined".to_string(), |v| format!("{v:.3}"));
            lines.push(format!("{name:<16} {value:>10}  {verdict:<7} [{}, {}]", s.min, s.max));
        }
        let v = &survey.void_volume;
        let parts: Vec<String> = v
            .zones
            .iter()
            .chain(&v.conduit_types)
            .filter(|(_, m)| **m > 0.0)
            .map(|(k, m)| format!("{k} {m:.0}"))
            .collect();
        lines.push(format!("void volume {:.0} m³: {}", v.total, parts.join(", ")));
        lines
    }

    /// `passages.csv`: one row per station.
    fn side_files(
        out: &Path,
        _: &SurveyView,
        _: &(Skeleton, SdfModel),
        survey: &mut Survey,
    ) -> std::io::Result<()> {
        write_csv(&out.join("passages.csv"), survey)
    }
}

/// Writes the stations as `conduit,station,x,y,z,cs_width,cs_height,type,zone,junction`.
pub fn write_csv(path: &Path, survey: &Survey) -> std::io::Result<()> {
    let mut text = String::from("conduit,station,x,y,z,cs_width,cs_height,type,zone,junction\n");
    for s in &survey.stations {
        let [x, y, z] = s.position;
        text.push_str(&format!(
            "{},{},{x:.3},{y:.3},{z:.3},{:.3},{:.3},{},{},{}\n",
            s.conduit,
            s.station,
            s.width,
            s.height,
            if s.shaft { "shaft" } else { s.kind.name() },
            zone_name(s.zone),
            u8::from(s.junction)
        ));
    }
    std::fs::File::create(path)?.write_all(text.as_bytes())
}
