//! Typed views of a scene: what one stage may read of it.
//!
//! A stage's artifact key hashes the scene sections the stage reads, so that editing any other
//! section leaves the artifact up to date. A stage never sees the whole [`Scene`]: it declares
//! a view with [`view!`](crate::view!), a struct of typed references to the sections it reads
//! (`&Domain`, `&[KeyPoint]`, `&HydroParams`, one field of a section such as
//! `skeleton.forced_links`), and the runner builds that view from the scene. The list of
//! sections the key hashes ([`SceneView::SECTIONS`]) is generated from the same field list as
//! the struct, so what a stage can read and what its key covers cannot differ.
//!
//! Every view also carries what is no section: the memory budget (`--max-memory`) and the
//! output budget of a run (`karstgen run --budget`), both in no key (they decide whether a
//! stage refuses, never what it writes), and the local frame (origin and
//! CRS, in every key: see `karst_artifact::stages::stage_key`).

use serde::Serialize;

use crate::params::{
    CalibrateParams, CostgraphParams, ExportParams, HydroParams, MesherParams, SamplingParams, SdfParams,
    SkeletonParams, StreamsParams,
};
use crate::sections::Section;
use crate::{KeyPoint, Phase, Scene};

pub use karst_artifact::Frame;

/// What one stage reads of a scene; declared with [`view!`](crate::view!).
pub trait SceneView<'s>: Sized {
    /// The sections of the view's fields, in the order its key hashes them.
    const SECTIONS: &'static [Section];

    /// The view of `scene`.
    fn of(scene: &'s Scene) -> Self;

    /// The hash of the view's sections: [`Scene::sections_hash`] of [`SceneView::SECTIONS`]
    /// for the scene the view was made of.
    fn sections_hash(&self) -> String;
}

/// One part of a scene a view can hold: a section, or one field of one.
pub trait Part<'s> {
    /// The section it is.
    const SECTION: Section;
    /// What a view holds of it: a reference, or a number.
    type Ref: Copy + std::fmt::Debug + Serialize;

    /// The part of `scene`.
    fn of(scene: &'s Scene) -> Self::Ref;

    /// Its value as the key hashes it: the JSON the scene file's own serialization gives it.
    fn json(part: &Self::Ref) -> serde_json::Value {
        to_json(part)
    }
}

fn to_json(value: &impl Serialize) -> serde_json::Value {
    serde_json::to_value(value).expect("a scene always serializes")
}

/// The hash of sections given with their values ([`Part::json`]), for artifact keys. A part
/// added after keys were first written hashes as absent (null) at the value that reproduces the
/// artifacts written before it existed (`sdf.passage_detail = "off"`, no `calibrate.like` nor
/// `target`), so that their keys stay.
pub fn hash(values: &[(Section, serde_json::Value)]) -> String {
    let texts: Vec<String> = values
        .iter()
        .filter(|(section, value)| {
            !(matches!(section, Section::PassageDetail | Section::CalibrationAim) && value.is_null())
        })
        .map(|(section, value)| format!("{}={value}", section.key()))
        .collect();
    karst_artifact::hash::hex_of_parts(texts.iter().map(|t| t.as_bytes()))
}

/// The parts, one marker type per section, named as the section's [`Section`] variant.
pub mod part {
    use super::*;

    macro_rules! parts {
        ($($(#[$doc:meta])* $name:ident: $ty:ty = |$scene:ident| $get:expr $(, json |$part:ident| $json:expr)?;)*) => {
            $(
                $(#[$doc])*
                #[derive(Debug, Clone, Copy)]
                pub struct $name;

                impl<'s> Part<'s> for $name {
                    const SECTION: Section = Section::$name;
                    type Ref = $ty;

                    #[inline]
                    fn of($scene: &'s Scene) -> $ty {
                        $get
                    }

                    $(
                        fn json($part: &$ty) -> serde_json::Value {
                            $json
                        }
                    )?
                }
            )*

            /// The value of `section` in `scene` as the key hashes it.
            pub(crate) fn json(scene: &Scene, section: Section) -> serde_json::Value {
                match section {
                    $(Section::$name => <$name as Part>::json(&<$name as Part>::of(scene)),)*
                }
            }
        };
    }

    parts! {
        /// `seed`: the seed of every random choice.
        Seed: u64 = |scene| scene.seed;
        /// `[domain]`: the box of the model.
        Domain: &'s karst_geology::Domain = |scene| &scene.domain;
        /// `[terrain]`: the ground surface.
        Terrain: &'s karst_geology::Terrain = |scene| &scene.terrain;
        /// `[geology]`: water tables, horizons, faults, fractures, layers, potential, no-karst.
        Geology: &'s karst_geology::Geology = |scene| &scene.geology;
        /// `[[keypoints]]` (and `[[keypoints_from]]`'s points): sinks, springs, waypoints, dead
        /// ends, in scene order.
        Keypoints: &'s [KeyPoint] = |scene| &scene.keypoints;
        /// `[connectivity]`: which sink may drain to which spring.
        Connectivity: &'s crate::Connectivity = |scene| &scene.connectivity;
        /// `[[phases]]`: speleogenetic phases, oldest first.
        /// The scene file leaves out an empty list: its key hashes it as absent.
        Phases: &'s [Phase] = |scene| &scene.phases, json |phases| {
            if phases.is_empty() { serde_json::Value::Null } else { super::to_json(phases) }
        };
        /// `[sampling]`.
        Sampling: &'s SamplingParams = |scene| &scene.sampling;
        /// `[costgraph]`.
        Costgraph: &'s CostgraphParams = |scene| &scene.costgraph;
        /// `[skeleton]`.
        Skeleton: &'s SkeletonParams = |scene| &scene.skeleton;
        /// `skeleton.forced_links`, read on its own by the cost graph.
        ForcedLinks: &'s [[String; 2]] = |scene| &scene.skeleton.forced_links;
        /// `[hydro]`.
        Hydro: &'s HydroParams = |scene| &scene.hydro;
        /// `hydro.total_discharge`, read on its own by the streams (the springs' discharge in
        /// m³/s).
        TotalDischarge: f64 = |scene| scene.hydro.total_discharge;
        /// `[streams]`: the surface streams and their controller curves.
        Streams: &'s StreamsParams = |scene| &scene.streams;
        /// `[sdf]`; `passage_detail = "off"` hashes as absent (see [`hash`](super::hash)), and
        /// the fields only `full` reads are left out below `full`.
        Sdf: &'s SdfParams = |scene| &scene.sdf, json |sdf| {
            let mut value = super::to_json(sdf);
            if let Some(fields) = value.as_object_mut() {
                if !sdf.passage_detail.varies() {
                    fields.remove("passage_detail");
                }
                if !sdf.passage_detail.features() {
                    for name in crate::params::FULL_DETAIL_FIELDS {
                        fields.remove(name);
                    }
                }
            }
            value
        };
        /// `sdf.passage_detail`, read on its own by the skeleton (the passages' size and shape
        /// along the conduits); `off` hashes as absent (see [`hash`](super::hash)).
        PassageDetail: crate::params::PassageDetail = |scene| scene.sdf.passage_detail, json |detail| {
            if detail.varies() { super::to_json(detail) } else { serde_json::Value::Null }
        };
        /// `[mesher]`.
        Mesher: &'s MesherParams = |scene| &scene.mesher;
        /// `[export]`: which formats the export stage writes.
        Export: &'s ExportParams = |scene| &scene.export;
        /// `[calibrate]`: the parameter box of `karstgen calibrate`, when the scene has one.
        Calibrate: Option<&'s CalibrateParams> = |scene| scene.calibrate.as_ref();
        /// `calibrate.like` or `calibrate.target` (with its file's BLAKE3), read on its own by
        /// the metrics stage; none hashes as absent (see [`hash`](super::hash)).
        CalibrationAim: Option<crate::params::Aim<'s>> = |scene| scene.calibrate.as_ref().and_then(|c| c.aim()), json |aim| {
            match aim {
                None => serde_json::Value::Null,
                Some(crate::params::Aim::Like(name)) => serde_json::json!({ "like": name }),
                Some(crate::params::Aim::Target { file, content, .. }) => {
                    serde_json::json!({ "target": file, "content": content })
                }
            }
        };
    }
}

/// Declares a stage's view of the scene: a struct with one typed field per section it reads
/// (each field names its part of [`view::part`](crate::view::part)), plus `budget` and `frame`,
/// and its [`SceneView`] implementation, whose [`SceneView::SECTIONS`] lists the fields'
/// sections in the order written.
///
/// ```
/// karst_scene::view! {
///     /// What the hydro stage reads.
///     pub struct HydroView<'s> { domain: Domain, terrain: Terrain, keypoints: Keypoints, hydro: Hydro }
/// }
/// # use karst_scene::{Section, view::SceneView};
/// assert_eq!(HydroView::SECTIONS, [Section::Domain, Section::Terrain, Section::Keypoints, Section::Hydro]);
/// ```
#[macro_export]
macro_rules! view {
    (
        $(#[$meta:meta])*
        $vis:vis struct $name:ident<$s:lifetime> {
            $($(#[$field_meta:meta])* $field:ident: $part:ident),* $(,)?
        }
    ) => {
        $(#[$meta])*
        #[derive(Debug, Clone, Copy)]
        $vis struct $name<$s> {
            $(
                $(#[$field_meta])*
                #[doc = concat!("Section `", stringify!($part), "` of the scene.")]
                pub $field: <$crate::view::part::$part as $crate::view::Part<$s>>::Ref,
            )*
            /// The memory the stage may plan to use (`--max-memory`): no section, in no key.
            pub budget: $crate::budget::Budget,
            /// The bytes the run's meshes and exports may take (`karstgen run --budget`), when
            /// the run holds them to it: no section, in no key.
            pub output_budget: Option<$crate::output_budget::OutputBudget>,
            /// The local frame the artifacts record (origin and CRS): no section, in every key.
            pub frame: &$s $crate::view::Frame,
        }

        impl<$s> $crate::view::SceneView<$s> for $name<$s> {
            const SECTIONS: &'static [$crate::Section] =
                &[$(<$crate::view::part::$part as $crate::view::Part<'static>>::SECTION),*];

            fn of(scene: &$s $crate::Scene) -> Self {
                $name {
                    $($field: <$crate::view::part::$part as $crate::view::Part<$s>>::of(scene),)*
                    budget: scene.budget(),
                    output_budget: scene.output_budget(),
                    frame: scene.frame(),
                }
            }

            fn sections_hash(&self) -> String {
                $crate::view::hash(&[$((
                    <$crate::view::part::$part as $crate::view::Part<$s>>::SECTION,
                    <$crate::view::part::$part as $crate::view::Part<$s>>::json(&self.$field),
                )),*])
            }
        }
    };
}
