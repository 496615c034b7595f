//! The sampling stage's contract: its view of the scene in, `samples.bin` out.

use karst_artifact::{Header, StageId};
use karst_stage::Stage;

use crate::build::build;
use crate::error::SamplingError;
use crate::payload::Samples;
use crate::view::SamplingView;

/// Stage 1: Poisson-disk samples of the bedrock.
pub struct SamplingStage;

impl Stage for SamplingStage {
    const ID: StageId = StageId::Sampling;
    type Inputs = ();
    type Output = Samples;
    type Error = SamplingError;
    type View<'s> = SamplingView<'s>;

    fn build(view: &SamplingView, _: &()) -> Result<Samples, SamplingError> {
        build(view)
    }

    fn headline(_: &SamplingView, samples: &Samples) -> String {
        let c = samples.tag_counts();
        format!(
            "{} samples ({} key points, {} on water tables, {} on horizons, {} on faults)",
            samples.len(),
            c.keypoint,
            c.water_table,
            c.horizon,
            c.fault
        )
    }

    fn summary(header: &Header, samples: &Samples) -> Vec<String> {
        let c = samples.tag_counts();
        let f = &samples.radius_field;
        let mut lines = vec![
            format!("samples     {}", samples.len()),
            format!("volume      {}", c.volume),
            format!("key points  {}", c.keypoint),
            format!("water table {}", c.water_table),
            format!("horizons    {}", c.horizon),
            format!("faults      {}", c.fault),
            format!(
                "radius      {} m at the smallest, field of {:?} nodes every {} m",
                samples.radius, f.size, f.cell
            ),
        ];
        if let Some((lo, hi)) = bounds(&samples.positions) {
            // World coordinates: the local bounds plus the frame's origin.
            let (lo, hi) = (header.frame().world(lo), header.frame().world(hi));
            lines.push(format!(
                "bounds      [{:.2}, {:.2}, {:.2}] – [{:.2}, {:.2}, {:.2}]",
                lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]
            ));
        }
        lines.push(format!(
            "bytes       {} payload ({:.1} per sample)",
            header.payload_len,
            header.payload_len as f64 / samples.len().max(1) as f64
        ));
        lines
    }
}

fn bounds(points: &[[f64; 3]]) -> Option<([f64; 3], [f64; 3])> {
    let first = *points.first()?;
    Some(points.iter().fold((first, first), |(mut lo, mut hi), p| {
        for a in 0..3 {
            lo[a] = lo[a].min(p[a]);
            hi[a] = hi[a].max(p[a]);
        }
        (lo, hi)
    }))
}
