//! [`Crs`]: the coordinate reference system a grid's coordinates are in, as files name it.

use serde::{Deserialize, Serialize};

use crate::{HeightfieldError, Units};

/// A coordinate reference system as a file names it: an EPSG code, a WKT definition (OGC WKT 1 as
/// GDAL and `.prj` files write it, or WKT 2), or both.
///
/// relief does not reproject; it keeps the CRS it read so that every writer can label its output
/// the same way (`GeoTIFF` geo keys, `.prj`, metadata, the `GeoJSON` `crs` member), and takes the
/// grid's [`Units`] from it ([`Crs::units`]). Reading EPSG tables is the IO crate's job
/// (`relief-heightfield-io` fills in the WKT of a bare code).
///
/// In JSON: `{ "epsg": 32617 }`, `{ "wkt": "PROJCS[…]" }` or both; at least one is required.
///
/// ```
/// use relief_heightfield::{Crs, Units};
///
/// let utm = Crs::from_wkt(r#"PROJCS["WGS 84 / UTM zone 17N",GEOGCS["WGS 84",UNIT["degree",0.0174532925199433]],
///     PROJECTION["Transverse_Mercator"],UNIT["metre",1],AUTHORITY["EPSG","32617"]]"#)?;
/// assert_eq!(utm.epsg(), Some(32617));
/// assert_eq!(utm.name(), "WGS 84 / UTM zone 17N");
/// assert_eq!(utm.units(), Some(Units::Metres));
/// assert_eq!(Crs::from_epsg(4326)?.to_string(), "EPSG:4326");
/// # Ok::<(), relief_heightfield::HeightfieldError>(())
/// ```
#[derive(Debug, Clone, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(try_from = "CrsRepr", into = "CrsRepr")]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema))]
pub struct Crs {
    epsg: Option<u32>,
    wkt: Option<String>,
}

/// The JSON form of a [`Crs`].
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
#[cfg_attr(feature = "schemars", derive(schemars::JsonSchema), schemars(rename = "Crs"))]
struct CrsRepr {
    /// EPSG code, e.g. 32617 for WGS 84 / UTM zone 17N.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    epsg: Option<u32>,
    /// WKT definition.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    wkt: Option<String>,
}

impl TryFrom<CrsRepr> for Crs {
    type Error = HeightfieldError;
    fn try_from(r: CrsRepr) -> Result<Self, Self::Error> {
        match (r.epsg, r.wkt) {
            (epsg, Some(wkt)) => {
                let mut crs = Crs::from_wkt(&wkt)?;
                if epsg.is_some() {
                    crs.epsg = epsg;
                }
                Ok(crs)
            }
            (Some(code), None) => Crs::from_epsg(code),
            (None, None) => Err(HeightfieldError::InvalidCrs { reason: "give an epsg code or a wkt".to_owned() }),
        }
    }
}

impl From<Crs> for CrsRepr {
    fn from(c: Crs) -> Self {
        Self { epsg: c.epsg, wkt: c.wkt }
    }
}

impl Crs {
    /// The CRS with this EPSG code (its WKT unknown until someone looks it up).
    ///
    /// # Errors
    /// [`HeightfieldError::InvalidCrs`] for code 0 or a code above 999 999 (EPSG codes are at most
    /// six digits; 32767 means "user-defined" in `GeoTIFF` and is refused too).
    pub fn from_epsg(code: u32) -> Result<Self, HeightfieldError> {
        if code == 0 || code == 32767 || code > 999_999 {
            return Err(HeightfieldError::InvalidCrs { reason: format!("EPSG:{code} is not an EPSG code") });
        }
        Ok(Self { epsg: Some(code), wkt: None })
    }

    /// The CRS a WKT text defines; its EPSG code is taken from the root's `AUTHORITY["EPSG", n]`
    /// (WKT 1) or `ID["EPSG", n]` (WKT 2) when present.
    ///
    /// # Errors
    /// [`HeightfieldError::InvalidCrs`] when the text is not bracketed WKT.
    pub fn from_wkt(wkt: &str) -> Result<Self, HeightfieldError> {
        let text = wkt.trim().trim_start_matches('\u{feff}');
        let root = Node::parse(text)
            .ok_or_else(|| HeightfieldError::InvalidCrs { reason: format!("not WKT: {:?}", clip(text)) })?;
        let epsg = root
            .children
            .iter()
            .filter(|c| c.keyword_is(&["AUTHORITY", "ID"]))
            .find(|c| c.strings.first().is_some_and(|a| a.eq_ignore_ascii_case("EPSG")))
            .and_then(|c| {
                c.strings.get(1).and_then(|s| s.parse().ok()).or_else(|| c.numbers.first().map(|&n| n as u32))
            });
        Ok(Self { epsg, wkt: Some(text.to_owned()) })
    }

    /// The same CRS with its WKT definition filled in (for a CRS read as a bare EPSG code).
    #[must_use]
    pub fn with_wkt(mut self, wkt: impl Into<String>) -> Self {
        self.wkt = Some(wkt.into());
        self
    }

    /// The same CRS with its EPSG code filled in when its WKT carries no authority at all but
    /// defines one of the common two-dimensional geographic CRSs that ESRI `.prj` files and other
    /// tools write that way (`GEOGCS["GCS_WGS_1984",DATUM["D_WGS_1984",…]]`): WGS 84 (EPSG:4326),
    /// NAD83 (4269), NAD27 (4267) or ETRS89 (4258), told by the datum's name and checked against
    /// its ellipsoid, the prime meridian (Greenwich, or none given, which WKT 2 reads as Greenwich)
    /// and degrees, as GDAL identifies them. Anything else is returned as it is: a code is never
    /// guessed for a projected or 3D CRS, another datum, another meridian or unit, or a CRS that
    /// names another authority (OGC's `CRS84`, ESRI's, IGNF's).
    ///
    /// ```
    /// use relief_heightfield::Crs;
    ///
    /// let esri = r#"GEOGCS["GCS_WGS_1984",DATUM["D_WGS_1984",SPHEROID["WGS_1984",6378137.0,298.257223563]],PRIMEM["Greenwich",0.0],UNIT["Degree",0.0174532925199433]]"#;
    /// let crs = Crs::from_wkt(esri)?;
    /// assert_eq!(crs.epsg(), None);
    /// let crs = crs.identified();
    /// assert_eq!(crs.epsg(), Some(4326));
    /// assert_eq!(crs.wkt(), Some(esri), "the file's own definition is kept");
    /// # Ok::<(), relief_heightfield::HeightfieldError>(())
    /// ```
    #[must_use]
    pub fn identified(mut self) -> Self {
        if self.epsg.is_none() {
            self.epsg = self.root().as_ref().and_then(well_known_geographic);
        }
        self
    }

    /// The EPSG code, when known.
    pub fn epsg(&self) -> Option<u32> {
        self.epsg
    }

    /// The WKT definition, when known.
    pub fn wkt(&self) -> Option<&str> {
        self.wkt.as_deref()
    }

    /// The CRS's name: the WKT root's first string (`WGS 84 / UTM zone 17N`), or `EPSG:n`.
    pub fn name(&self) -> String {
        self.root().and_then(|r| r.strings.first().cloned()).unwrap_or_else(|| self.to_string())
    }

    /// Whether the WKT root is a local or engineering CRS (`LOCAL_CS`, `ENGCRS`): coordinates in
    /// some unit with no place on Earth.
    pub fn is_local(&self) -> bool {
        self.root().is_some_and(|r| r.keyword_is(&["LOCAL_CS", "ENGCRS", "ENGINEERINGCRS"]))
    }

    /// The units of the CRS's horizontal axes, read from its WKT: degrees for a geographic CRS;
    /// for a projected or local one the linear unit's length in metres (1 → metres, 0.3048 → feet,
    /// 0.304800609… → US survey feet). `None` without WKT, or for a unit relief does not know.
    pub fn units(&self) -> Option<Units> {
        let root = self.root()?;
        let horizontal = if root.keyword_is(&["COMPD_CS", "COMPOUNDCRS"]) { root.children.first()? } else { &root };
        if horizontal.keyword_is(&["GEOGCS", "GEOGCRS", "GEOGRAPHICCRS"]) {
            return Some(Units::Degrees);
        }
        let unit = horizontal.children.iter().find(|c| c.keyword_is(&["UNIT", "LENGTHUNIT"])).or_else(|| {
            let axes = horizontal.children.iter().filter(|c| c.keyword_is(&["AXIS"]));
            axes.flat_map(|a| &a.children).find(|c| c.keyword_is(&["UNIT", "LENGTHUNIT"]))
        })?;
        if horizontal.keyword_is(&["GEODCRS", "GEODETICCRS"]) {
            return None;
        }
        linear_units(*unit.numbers.first()?)
    }

    fn root(&self) -> Option<Node> {
        Node::parse(self.wkt.as_deref()?)
    }
}

impl std::fmt::Display for Crs {
    /// `EPSG:n` when the code is known, else the WKT's name.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match (self.epsg, self.root().and_then(|r| r.strings.first().cloned())) {
            (Some(code), _) => write!(f, "EPSG:{code}"),
            (None, Some(name)) => f.write_str(&name),
            (None, None) => f.write_str("unnamed CRS"),
        }
    }
}

/// A geographic datum that files name without an authority: the names it goes by (upper case,
/// letters and digits only), its ellipsoid's semi-major axis and inverse flattening, and the EPSG
/// code of the geographic CRS on it in degrees from Greenwich.
struct KnownDatum {
    names: &'static [&'static str],
    a: f64,
    inverse_flattening: f64,
    code: u32,
}

/// The datums [`Crs::identified`] knows. GRS 1980 (NAD83's and ETRS89's ellipsoid) differs from
/// WGS 84's in the ninth digit of the inverse flattening, which the check tells apart.
const KNOWN_DATUMS: [KnownDatum; 4] = [
    KnownDatum::new(&["WGS1984", "WGS84", "WORLDGEODETICSYSTEM1984"], 6_378_137.0, 298.257_223_563, 4326),
    KnownDatum::new(&["NORTHAMERICAN1983", "NORTHAMERICANDATUM1983", "NAD83"], 6_378_137.0, 298.257_222_101, 4269),
    KnownDatum::new(&["NORTHAMERICAN1927", "NORTHAMERICANDATUM1927", "NAD27"], 6_378_206.4, 294.978_698_213_898, 4267),
    KnownDatum::new(
        &["ETRS1989", "ETRS89", "EUROPEANTERRESTRIALREFERENCESYSTEM1989"],
        6_378_137.0,
        298.257_222_101,
        4258,
    ),
];

impl KnownDatum {
    const fn new(names: &'static [&'static str], a: f64, inverse_flattening: f64, code: u32) -> Self {
        Self { names, a, inverse_flattening, code }
    }
}

/// The EPSG code of a geographic CRS `root` (WKT 1 or 2, with no authority of its own) on one of
/// the [`KNOWN_DATUMS`], with its ellipsoid, the Greenwich meridian and degrees.
fn well_known_geographic(root: &Node) -> Option<u32> {
    if !root.keyword_is(&["GEOGCS", "GEOGCRS", "GEOGRAPHICCRS"]) {
        return None;
    }
    // Any authority of its own (OGC's CRS84, ESRI's, IGNF's) says what it is better than a guess.
    if root.children.iter().any(|c| c.keyword_is(&["AUTHORITY", "ID"])) {
        return None;
    }
    // Two axes only: WGS 84 with ellipsoidal heights (3D) is another CRS (EPSG:4979).
    let three_d = root.children.iter().any(|c| c.keyword_is(&["CS"]) && c.numbers.first().is_some_and(|&n| n > 2.0));
    if three_d || root.children.iter().filter(|c| c.keyword_is(&["AXIS"])).count() > 2 {
        return None;
    }
    let datum = root.children.iter().find(|c| c.keyword_is(&["DATUM", "GEODETICDATUM", "TRF"]))?;
    let name: String = datum.strings.first()?.chars().filter(char::is_ascii_alphanumeric).collect();
    let name = name.to_ascii_uppercase();
    // ESRI prefixes datum names with `D_`.
    let esri = datum.strings.first()?.to_ascii_uppercase().starts_with("D_");
    let name = if esri { &name[1..] } else { &name[..] };
    let known = KNOWN_DATUMS.iter().find(|d| d.names.contains(&name))?;
    let ellipsoid = datum.children.iter().find(|c| c.keyword_is(&["SPHEROID", "ELLIPSOID"]))?;
    let close = |v: f64, w: f64| ((v - w) / w).abs() < 1e-9;
    let [a, rf, ..] = ellipsoid.numbers[..] else { return None };
    if !(close(a, known.a) && close(rf, known.inverse_flattening)) {
        return None;
    }
    let greenwich = root
        .children
        .iter()
        .filter(|c| c.keyword_is(&["PRIMEM", "PRIMEMERIDIAN"]))
        .all(|m| m.numbers.first() == Some(&0.0));
    let axes = root.children.iter().filter(|c| c.keyword_is(&["AXIS"])).flat_map(|a| &a.children);
    let mut units = root.children.iter().chain(axes).filter(|c| c.keyword_is(&["UNIT", "ANGLEUNIT"])).peekable();
    let degrees = units.peek().is_some()
        && units.all(|u| u.numbers.first().is_some_and(|&r| close(r, std::f64::consts::PI / 180.0)));
    (greenwich && degrees).then_some(known.code)
}

/// The planar [`Units`] whose length in metres is `metres` (to 1e-7 relative).
fn linear_units(metres: f64) -> Option<Units> {
    [Units::Metres, Units::Feet, Units::UsSurveyFeet]
        .into_iter()
        .find(|u| u.metres().is_some_and(|m| ((metres - m) / m).abs() < 1e-7))
}

fn clip(text: &str) -> String {
    text.chars().take(40).collect()
}

/// One WKT node: `KEYWORD[ "string", number, CHILD[...], ... ]`.
struct Node {
    keyword: String,
    strings: Vec<String>,
    numbers: Vec<f64>,
    children: Vec<Node>,
}

impl Node {
    fn keyword_is(&self, names: &[&str]) -> bool {
        names.iter().any(|n| self.keyword.eq_ignore_ascii_case(n))
    }

    /// The root node of `text`, `None` unless the whole text is one well-formed node.
    fn parse(text: &str) -> Option<Node> {
        let text = text.trim();
        let mut chars = text.char_indices().peekable();
        let keyword = Self::word(text, &mut chars);
        let node = Self::parse_node(text, keyword, &mut chars, 0)?;
        chars.next().is_none().then_some(node)
    }

    /// The identifier at the cursor (possibly empty).
    fn word(text: &str, chars: &mut std::iter::Peekable<std::str::CharIndices<'_>>) -> String {
        let start = chars.peek().map_or(text.len(), |&(k, _)| k);
        while chars.peek().is_some_and(|&(_, c)| c.is_ascii_alphanumeric() || c == '_') {
            chars.next();
        }
        let end = chars.peek().map_or(text.len(), |&(k, _)| k);
        text[start..end].to_owned()
    }

    /// The node whose keyword was just read; the cursor is on its opening bracket.
    fn parse_node(
        text: &str,
        keyword: String,
        chars: &mut std::iter::Peekable<std::str::CharIndices<'_>>,
        depth: usize,
    ) -> Option<Node> {
        // WKT nests a handful of levels; a cap keeps hostile input from exhausting the stack.
        if depth > 64 || keyword.is_empty() || !matches!(chars.next()?.1, '[' | '(') {
            return None;
        }
        let mut node = Node { keyword, strings: Vec::new(), numbers: Vec::new(), children: Vec::new() };
        loop {
            while chars.peek().is_some_and(|&(_, c)| c.is_whitespace() || c == ',') {
                chars.next();
            }
            match chars.peek()?.1 {
                ']' | ')' => {
                    chars.next();
                    return Some(node);
                }
                '"' => {
                    chars.next();
                    let mut s = String::new();
                    loop {
                        let (_, c) = chars.next()?;
                        // WKT escapes a quote inside a string by doubling it.
                        if c == '"' && chars.next_if(|&(_, c)| c == '"').is_none() {
                            break;
                        }
                        s.push(c);
                    }
                    node.strings.push(s);
                }
                c if c.is_ascii_digit() || c == '-' || c == '+' || c == '.' => {
                    let from = chars.peek()?.0;
                    while chars.peek().is_some_and(|&(_, c)| !(c == ',' || c == ']' || c == ')' || c.is_whitespace())) {
                        chars.next();
                    }
                    let to = chars.peek()?.0;
                    node.numbers.push(text[from..to].parse().ok()?);
                }
                c if c.is_ascii_alphabetic() => {
                    let word = Self::word(text, chars);
                    while chars.peek().is_some_and(|&(_, c)| c.is_whitespace()) {
                        chars.next();
                    }
                    if chars.peek().is_some_and(|&(_, c)| c == '[' || c == '(') {
                        node.children.push(Self::parse_node(text, word, chars, depth + 1)?);
                    } else {
                        // A bare enumeration value such as `EAST` or `Cartesian`.
                        node.strings.push(word);
                    }
                }
                _ => return None,
            }
        }
    }
}
