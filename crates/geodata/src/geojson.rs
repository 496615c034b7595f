//! GeoJSON point collections: a `FeatureCollection` of `Point` features (RFC 7946), as a GIS
//! exports a layer of sinks, springs or boreholes.
//!
//! Each feature gives its position (`[x, y]` or `[x, y, z]`) and its properties, looked up by
//! name exactly or, failing that, without regard to case (`Name` for `name`). The optional `crs`
//! member of the 2008 specification (`{"type": "name", "properties": {"name":
//! "urn:ogc:def:crs:EPSG::2154"}}`), which GIS exports still write for projected layers, is read
//! as an EPSG code; karstgen does not reproject, so the caller checks it against the scene's.
//! A feature that is not a Point is an error of that feature alone: the caller can report every
//! bad feature of a file at once.

use serde_json::Value;

use crate::crs::Epsg;

/// A GeoJSON FeatureCollection read as points.
#[derive(Debug, Clone)]
pub struct PointCollection {
    /// The EPSG code of the collection's `crs` member, if it has one.
    pub crs: Option<Epsg>,
    /// Each feature in file order: its point, or why it is not one.
    pub features: Vec<Result<PointFeature, FeatureError>>,
}

/// One Point feature: its coordinates and properties.
#[derive(Debug, Clone)]
pub struct PointFeature {
    /// Easting and northing, the first two coordinates.
    pub xy: [f64; 2],
    /// Elevation, the third coordinate when the Point has one.
    pub z: Option<f64>,
    properties: serde_json::Map<String, Value>,
}

/// A property's value, as a table's cell: empty strings and `null` are absent.
#[derive(Debug, Clone, PartialEq)]
pub enum Property {
    /// A non-empty string.
    Text(String),
    /// A JSON number.
    Number(f64),
    /// An array, each item as text (strings unquoted).
    List(Vec<String>),
}

/// Why a file is not a GeoJSON point collection.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GeoJsonError {
    /// Not JSON: the line of the first syntax error and serde_json's description.
    #[error("{line}: {message}")]
    Syntax { line: usize, message: String },
    /// A JSON document whose `type` is not `FeatureCollection`.
    #[error("is a {found}, not a GeoJSON FeatureCollection")]
    NotCollection { found: String },
    /// A `crs` member whose name is not an EPSG code.
    #[error("crs \"{name}\" is not an EPSG code (urn:ogc:def:crs:EPSG::NNNN)")]
    NotEpsg { name: String },
    /// A collection without its `features` array.
    #[error("has no \"features\" array")]
    NoFeatures,
}

/// Why one feature is not a point.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FeatureError {
    /// Another geometry (`a LineString`) or none (`no geometry`).
    #[error("is {found}: karstgen reads Point features only")]
    NotPoint { found: String },
    /// Coordinates that are not two or three numbers, as the file writes them.
    #[error("coordinates {found} are not [x, y] or [x, y, z] numbers")]
    Coordinates { found: String },
}

impl PointCollection {
    /// Parses the text of a GeoJSON file.
    pub fn parse(text: &str) -> Result<PointCollection, GeoJsonError> {
        let json: Value = serde_json::from_str(text)
            .map_err(|e| GeoJsonError::Syntax { line: e.line(), message: e.to_string() })?;
        if json["type"] != "FeatureCollection" {
            return Err(GeoJsonError::NotCollection { found: json["type"].to_string() });
        }
        let crs = match &json["crs"]["properties"]["name"] {
            Value::Null => None,
            name => {
                let name = name.as_str().unwrap_or_default();
                Some(Epsg::from_name(name).ok_or_else(|| GeoJsonError::NotEpsg { name: name.into() })?)
            }
        };
        let features = json["features"].as_array().ok_or(GeoJsonError::NoFeatures)?;
        Ok(PointCollection { crs, features: features.iter().map(PointFeature::of).collect() })
    }
}

impl PointFeature {
    /// The point of one feature of the collection.
    fn of(feature: &Value) -> Result<PointFeature, FeatureError> {
        let geometry = &feature["geometry"];
        if geometry["type"] != "Point" {
            let found = geometry["type"].as_str().map_or("no geometry".to_string(), |t| format!("a {t}"));
            return Err(FeatureError::NotPoint { found });
        }
        let raw = geometry["coordinates"].as_array();
        let coordinates: Vec<f64> =
            raw.map(|c| c.iter().filter_map(Value::as_f64).collect()).unwrap_or_default();
        if !(2..=3).contains(&coordinates.len()) || raw.map(Vec::len) != Some(coordinates.len()) {
            return Err(FeatureError::Coordinates { found: geometry["coordinates"].to_string() });
        }
        let properties = feature["properties"].as_object().cloned().unwrap_or_default();
        Ok(PointFeature { xy: [coordinates[0], coordinates[1]], z: coordinates.get(2).copied(), properties })
    }

    /// The property `name` (exactly, else without regard to case); None when absent, `null` or an
    /// empty string.
    pub fn property(&self, name: &str) -> Option<Property> {
        let value = self
            .properties
            .get(name)
            .or_else(|| self.properties.iter().find(|(k, _)| k.eq_ignore_ascii_case(name)).map(|(_, v)| v))?;
        match value {
            Value::String(s) if !s.is_empty() => Some(Property::Text(s.clone())),
            Value::Number(n) => n.as_f64().map(Property::Number),
            Value::Array(items) => Some(Property::List(
                items.iter().map(|v| v.as_str().map_or(v.to_string(), str::to_string)).collect(),
            )),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn collection(features: &str, crs: &str) -> String {
        format!(r#"{{"type": "FeatureCollection", {crs} "features": [{features}]}}"#)
    }

    #[test]
    fn reads_points_their_properties_and_the_crs() {
        let crs = r#""crs": {"type": "name", "properties": {"name": "urn:ogc:def:crs:EPSG::2154"}},"#;
        let text = collection(
            r#"{"type": "Feature", "geometry": {"type": "Point", "coordinates": [1.5, 2, 3]},
                "properties": {"Name": "S1", "weight": 4, "phase": ["old", "new"], "empty": ""}},
               {"type": "Feature", "geometry": {"type": "Point", "coordinates": [5, 6]}, "properties": null}"#,
            crs,
        );
        let c = PointCollection::parse(&text).unwrap();
        assert_eq!(c.crs, Some(Epsg(2154)));
        let first = c.features[0].as_ref().unwrap();
        assert_eq!((first.xy, first.z), ([1.5, 2.0], Some(3.0)));
        assert_eq!(first.property("name"), Some(Property::Text("S1".into())));
        assert_eq!(first.property("WEIGHT"), Some(Property::Number(4.0)));
        assert_eq!(first.property("phase"), Some(Property::List(vec!["old".into(), "new".into()])));
        assert_eq!(first.property("empty"), None);
        assert_eq!(first.property("absent"), None);
        let second = c.features[1].as_ref().unwrap();
        assert_eq!((second.xy, second.z, second.property("name")), ([5.0, 6.0], None, None));
    }

    #[test]
    fn bad_features_are_named_one_by_one() {
        let text = collection(
            r#"{"type": "Feature", "geometry": {"type": "LineString", "coordinates": [[0, 0], [1, 1]]}},
               {"type": "Feature"},
               {"type": "Feature", "geometry": {"type": "Point", "coordinates": [1, "2"]}},
               {"type": "Feature", "geometry": {"type": "Point", "coordinates": [1, 2, 3, 4]}}"#,
            "",
        );
        let c = PointCollection::parse(&text).unwrap();
        let errors: Vec<String> = c.features.iter().map(|f| f.as_ref().unwrap_err().to_string()).collect();
        assert_eq!(errors[0], "is a LineString: karstgen reads Point features only");
        assert_eq!(errors[1], "is no geometry: karstgen reads Point features only");
        assert_eq!(errors[2], "coordinates [1,\"2\"] are not [x, y] or [x, y, z] numbers");
        assert_eq!(errors[3], "coordinates [1,2,3,4] are not [x, y] or [x, y, z] numbers");
    }

    #[test]
    fn files_that_are_not_point_collections_are_refused() {
        let err = |text: &str| PointCollection::parse(text).unwrap_err();
        assert!(matches!(err("{\"type\": "), GeoJsonError::Syntax { line: 1, .. }));
        assert_eq!(
            err(r#"{"type": "Feature"}"#).to_string(),
            "is a \"Feature\", not a GeoJSON FeatureCollection"
        );
        assert_eq!(err(r#"{"type": "FeatureCollection"}"#), GeoJsonError::NoFeatures);
        let crs84 = collection("", r#""crs": {"properties": {"name": "urn:ogc:def:crs:OGC:1.3:CRS84"}},"#);
        assert_eq!(err(&crs84), GeoJsonError::NotEpsg { name: "urn:ogc:def:crs:OGC:1.3:CRS84".into() });
    }
}
