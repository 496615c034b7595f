//! Stage 8: the passages measured as a cave survey would (issue 39), on the carved geometry of
//! `sdf.bin`.
//!
//! A station every [`SPACING`] metres of arc length along every conduit of the skeleton; at
//! each, in the plane through the station perpendicular to the passage, the open region of the
//! cave (the cave alone, under the ground) that holds the centreline point, or the nearest one
//! when a wall covers it, and in it the horizontal and the vertical chord through that point:
//! a surveyor's left + right and up + down (`measure.rs`). Shafts (steeper than 45°) carry two
//! horizontal chords instead. The area of that open region gives the void volume per zone and
//! conduit type (`area.rs`). The nine statistics of the table, over the stations that
//! are neither shafts nor within a passage width of a junction, are compared with the ranges of
//! 17 surveyed caves (`statistics.rs`, `fixtures/passages/passage-ranges.json`). [`build`] is
//! the entry (`build.rs`, stations placed by `stations.rs`), [`SurveyStage`] the stage. Output:
//! `survey.json` ([`Survey`], `payload.rs`) and `passages.csv`. See docs/metrics.md.

mod area;
mod build;
mod error;
mod measure;
mod payload;
mod ranges;
pub mod stage;
mod stations;
mod statistics;
mod view;

pub use build::build;
pub use error::SurveyError;
pub use measure::{Chords, measure};
pub use payload::{PassageStatistic, Station, Survey, VoidVolume};
pub use ranges::{PassageRange, passage_ranges};
pub use stage::SurveyStage;
pub use stations::SPACING;
pub use view::SurveyView;
