//! The layers' default QGIS styles (QML documents, stored in the GeoPackage's `layer_styles`
//! table with `useAsDefault`, which QGIS applies when it opens a layer): conduits, segments
//! and passages coloured by conduit type ([`CONDUIT_COLOURS`], the same colours as the
//! docs' figures use for the types), key points by kind, streams in blue, routes dashed.

use karst_skeleton::ConduitType;

/// The colour of every conduit type, `r,g,b` (ColorBrewer's Dark2 and Set1, told apart on a
/// hillshade).
pub const CONDUIT_COLOURS: [(ConduitType, [u8; 3]); 7] = [
    (ConduitType::Epikarst, [166, 118, 29]),
    (ConduitType::Tube, [31, 120, 180]),
    (ConduitType::Canyon, [227, 26, 28]),
    (ConduitType::Keyhole, [255, 127, 0]),
    (ConduitType::Passage, [51, 160, 44]),
    (ConduitType::Bed, [106, 61, 154]),
    (ConduitType::Chamber, [231, 41, 138]),
];

/// How a layer is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Shape {
    Line,
    Fill,
}

fn rgba([r, g, b]: [u8; 3], alpha: u8) -> String {
    format!("{r},{g},{b},{alpha}")
}

/// One `<Option>` of a symbol layer's property map.
fn option(name: &str, value: &str) -> String {
    format!("<Option name=\"{name}\" type=\"QString\" value=\"{value}\"/>")
}

/// A symbol of one symbol layer: `class` (SimpleLine, SimpleFill, SimpleMarker) and its
/// properties.
fn symbol(name: &str, kind: &str, class: &str, properties: &[(&str, String)]) -> String {
    let options: String = properties.iter().map(|(k, v)| option(k, v)).collect();
    format!(
        "<symbol name=\"{name}\" type=\"{kind}\" alpha=\"1\" clip_to_extent=\"1\" force_rhr=\"0\">\
         <layer class=\"{class}\" enabled=\"1\" locked=\"0\" pass=\"0\"><Option type=\"Map\">{options}</Option></layer>\
         </symbol>"
    )
}

fn line_symbol(name: &str, colour: [u8; 3], width_mm: f64, dashed: bool) -> String {
    symbol(
        name,
        "line",
        "SimpleLine",
        &[
            ("line_color", rgba(colour, 255)),
            ("line_width", width_mm.to_string()),
            ("line_width_unit", "MM".into()),
            ("line_style", if dashed { "dash" } else { "solid" }.into()),
            ("capstyle", "round".into()),
            ("joinstyle", "round".into()),
        ],
    )
}

fn fill_symbol(name: &str, colour: [u8; 3]) -> String {
    symbol(
        name,
        "fill",
        "SimpleFill",
        &[
            ("color", rgba(colour, 255)),
            ("style", "solid".into()),
            ("outline_color", rgba(colour, 255)),
            ("outline_width", "0.1".into()),
            ("outline_width_unit", "MM".into()),
        ],
    )
}

fn marker_symbol(name: &str, shape: &str, colour: [u8; 3], size_mm: f64) -> String {
    symbol(
        name,
        "marker",
        "SimpleMarker",
        &[
            ("name", shape.into()),
            ("color", rgba(colour, 255)),
            ("outline_color", "0,0,0,255".into()),
            ("outline_width", "0.2".into()),
            ("size", size_mm.to_string()),
            ("size_unit", "MM".into()),
        ],
    )
}

fn document(renderer: &str, opacity: f64) -> String {
    format!(
        "<!DOCTYPE qgis PUBLIC 'http://mrcc.com/qgis.dtd' 'SYSTEM'>\n\
         <qgis version=\"3.22.0\" styleCategories=\"Symbology\">{renderer}<layerOpacity>{opacity}</layerOpacity></qgis>\n"
    )
}

/// A renderer drawing each value of `attribute` with its symbol.
fn categorized(attribute: &str, categories: &[(&str, String)]) -> String {
    let list: String = categories
        .iter()
        .enumerate()
        .map(|(i, (value, _))| {
            format!("<category render=\"true\" value=\"{value}\" symbol=\"{i}\" label=\"{value}\"/>")
        })
        .collect();
    let symbols: String = categories.iter().map(|(_, s)| s.as_str()).collect();
    format!(
        "<renderer-v2 type=\"categorizedSymbol\" attr=\"{attribute}\" symbollevels=\"0\" enableorderby=\"0\" forceraster=\"0\">\
         <categories>{list}</categories><symbols>{symbols}</symbols></renderer-v2>"
    )
}

fn single(symbol: String) -> String {
    format!(
        "<renderer-v2 type=\"singleSymbol\" symbollevels=\"0\" enableorderby=\"0\" forceraster=\"0\"><symbols>{symbol}</symbols></renderer-v2>"
    )
}

/// Lines or fills coloured by the `type` column.
pub fn by_conduit_type(shape: Shape) -> String {
    let categories: Vec<(&str, String)> = CONDUIT_COLOURS
        .iter()
        .enumerate()
        .map(|(i, (ty, colour))| {
            let name = i.to_string();
            let symbol = match shape {
                Shape::Line => line_symbol(&name, *colour, 0.8, false),
                Shape::Fill => fill_symbol(&name, *colour),
            };
            (ty.name(), symbol)
        })
        .collect();
    let opacity = if shape == Shape::Fill { 0.4 } else { 1.0 };
    document(&categorized("type", &categories), opacity)
}

/// Sinks as blue triangles, springs as cyan circles, the other key points as grey squares.
pub fn key_points() -> String {
    let categories = [
        ("sink", marker_symbol("0", "triangle", [8, 48, 107], 3.0)),
        ("spring", marker_symbol("1", "circle", [0, 200, 220], 3.0)),
        ("waypoint", marker_symbol("2", "square", [120, 120, 120], 2.4)),
        ("dead_end", marker_symbol("3", "cross_fill", [120, 120, 120], 2.4)),
    ];
    document(&categorized("kind", &categories), 1.0)
}

/// Surface streams: thin blue lines.
pub fn streams() -> String {
    document(&single(line_symbol("0", [43, 140, 190], 0.5, false)), 1.0)
}

/// Routes: dashed dark grey lines.
pub fn routes() -> String {
    document(&single(line_symbol("0", [60, 60, 60], 0.3, true)), 1.0)
}
