//! A scene's target histogram: one of the library's [`Histogram`] forms, or a DEM file whose
//! elevations it takes.
//!
//! In JSON both are one-key objects (`{ "bins": … }`, `{ "samples": … }`, `{ "uniform": … }`,
//! `{ "dem": "real.asc" }`), so the key decides: `dem` is read here, every other key is handed to
//! the library's own deserializer, which validates the histogram and names any bad field by its
//! JSON path (`generator.contours.histogram.bins.edges[2]`).

use std::borrow::Cow;
use std::fmt;
use std::path::PathBuf;

use schemars::{JsonSchema, Schema, SchemaGenerator, json_schema};
use serde::de::{self, DeserializeSeed, Deserializer, EnumAccess, IntoDeserializer, MapAccess, VariantAccess, Visitor};
use serde::ser::SerializeMap;
use serde::{Deserialize, Serialize, Serializer};

use crate::contours::{Histogram, HistogramSpec};

/// Where a contour scene's target distribution of elevations comes from.
#[derive(Debug, Clone, PartialEq)]
pub enum HistogramSource {
    /// A histogram written in the scene.
    Histogram(Histogram),
    /// The elevations of a real DEM's land (any heightfield-io format), relative to the scene
    /// file: a flat sea at its lowest elevation (1 % of the samples or more) is left out.
    Dem(PathBuf),
}

impl Serialize for HistogramSource {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            Self::Histogram(h) => h.serialize(s),
            Self::Dem(path) => {
                let mut map = s.serialize_map(Some(1))?;
                map.serialize_entry("dem", path)?;
                map.end()
            }
        }
    }
}

impl<'de> Deserialize<'de> for HistogramSource {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_map(SourceVisitor)
    }
}

struct SourceVisitor;

impl<'de> Visitor<'de> for SourceVisitor {
    type Value = HistogramSource;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(r#"a histogram: { "bins": … }, { "samples": […] }, { "uniform": … } or { "dem": "file" }"#)
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<HistogramSource, A::Error> {
        let Some(key) = map.next_key::<String>()? else {
            return Err(de::Error::invalid_length(0, &self));
        };
        let source = if key == "dem" {
            HistogramSource::Dem(map.next_value()?)
        } else {
            let spec = HistogramSpec::deserialize(KeyedVariant { key, map: &mut map })?;
            HistogramSource::Histogram(Histogram::try_from(spec).map_err(de::Error::custom)?)
        };
        if let Some(extra) = map.next_key::<String>()? {
            return Err(de::Error::custom(format!("unexpected `{extra}`: give exactly one kind of histogram")));
        }
        Ok(source)
    }
}

/// An externally tagged enum value whose tag was already read from `map`: deserializes the
/// variant `key` from the map's next value, so the library type's own derive reads it.
struct KeyedVariant<'a, A> {
    key: String,
    map: &'a mut A,
}

impl<'de, A: MapAccess<'de>> Deserializer<'de> for KeyedVariant<'_, A> {
    type Error = A::Error;

    fn deserialize_any<V: Visitor<'de>>(self, visitor: V) -> Result<V::Value, A::Error> {
        visitor.visit_enum(self)
    }

    serde::forward_to_deserialize_any! {
        bool i8 i16 i32 i64 i128 u8 u16 u32 u64 u128 f32 f64 char str string bytes byte_buf option unit
        unit_struct newtype_struct seq tuple tuple_struct map struct enum identifier ignored_any
    }
}

impl<'de, A: MapAccess<'de>> EnumAccess<'de> for KeyedVariant<'_, A> {
    type Error = A::Error;
    type Variant = Self;

    fn variant_seed<S: DeserializeSeed<'de>>(self, seed: S) -> Result<(S::Value, Self), A::Error> {
        let tag = seed.deserialize(self.key.as_str().into_deserializer())?;
        Ok((tag, self))
    }
}

impl<'de, A: MapAccess<'de>> VariantAccess<'de> for KeyedVariant<'_, A> {
    type Error = A::Error;

    fn unit_variant(self) -> Result<(), A::Error> {
        self.map.next_value::<de::IgnoredAny>().map(|_| ())
    }

    fn newtype_variant_seed<S: DeserializeSeed<'de>>(self, seed: S) -> Result<S::Value, A::Error> {
        self.map.next_value_seed(seed)
    }

    fn tuple_variant<V: Visitor<'de>>(self, len: usize, visitor: V) -> Result<V::Value, A::Error> {
        self.map.next_value_seed(Shaped { fields: None, len, visitor })
    }

    fn struct_variant<V: Visitor<'de>>(
        self,
        fields: &'static [&'static str],
        visitor: V,
    ) -> Result<V::Value, A::Error> {
        self.map.next_value_seed(Shaped { fields: Some(fields), len: fields.len(), visitor })
    }
}

/// Reads a tuple or struct variant's body with the derive's own visitor.
struct Shaped<V> {
    fields: Option<&'static [&'static str]>,
    len: usize,
    visitor: V,
}

impl<'de, V: Visitor<'de>> DeserializeSeed<'de> for Shaped<V> {
    type Value = V::Value;

    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<V::Value, D::Error> {
        match self.fields {
            Some(fields) => d.deserialize_struct("", fields, self.visitor),
            None => d.deserialize_tuple(self.len, self.visitor),
        }
    }
}

impl JsonSchema for HistogramSource {
    fn schema_name() -> Cow<'static, str> {
        "HistogramSource".into()
    }

    fn json_schema(generator: &mut SchemaGenerator) -> Schema {
        let histogram = generator.subschema_for::<Histogram>();
        json_schema!({
            "description": "The target distribution of elevations: a histogram, or the elevations of a DEM file.",
            "oneOf": [
                histogram,
                {
                    "type": "object",
                    "properties": {
                        "dem": {
                            "description": "A DEM (any format relief reads), relative to the scene file: its elevations are the target.",
                            "type": "string"
                        }
                    },
                    "required": ["dem"],
                    "additionalProperties": false
                }
            ]
        })
    }
}
