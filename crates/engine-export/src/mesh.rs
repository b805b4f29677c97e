//! Terrain meshes as glTF 2.0 binaries (`.glb`): positions in metres, normals, UVs and optional
//! hypsometric vertex colours, decimated to an error bound or a triangle budget.

use std::borrow::Cow;
use std::collections::BTreeMap;
use std::path::Path;

use glam::{DVec2, DVec3};
use gltf::json;
use json::validation::Checked::Valid;
use json::validation::USize64;
use relief_heightfield::Heightfield;
use relief_tin::{Approximation, Tin};

use crate::EngineError;

/// At most this many triangles in one mesh (a 16-million-triangle `.glb` is about 600 MB).
pub const MAX_MESH_TRIANGLES: usize = 1 << 24;

/// How [`TerrainMesh::from_heightfield`] decimates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeshOptions {
    /// No sample farther than this from the mesh, vertically, in metres. Default: 0.1 % of the
    /// height range.
    pub max_error_m: Option<f64>,
    /// At most this many triangles (default 500 000, at most [`MAX_MESH_TRIANGLES`]); the mesh
    /// stops refining there even if the error bound is not yet met.
    pub max_triangles: usize,
    /// Vertex colours from the hypsometric ramp of the shaded previews (`COLOR_0`).
    pub colours: bool,
}

impl Default for MeshOptions {
    fn default() -> Self {
        Self { max_error_m: None, max_triangles: 500_000, colours: true }
    }
}

/// A terrain as a triangle mesh in metres: x east and y north of the south-west corner of its
/// bounds, z the elevation.
#[derive(Debug, Clone, PartialEq)]
pub struct TerrainMesh {
    /// Vertex positions, metres.
    pub positions: Vec<DVec3>,
    /// Counter-clockwise triangles seen from above.
    pub triangles: Vec<[u32; 3]>,
    /// The south-west corner's coordinates in the source's own units (grid or TIN).
    pub origin: DVec2,
    /// The largest vertical distance from a heightfield sample to the mesh, metres (0 for a TIN
    /// taken as is).
    pub max_error_m: f64,
}

impl MeshOptions {
    /// Checks the options as [`TerrainMesh::from_heightfield`] does before any work: the error
    /// bound finite and not negative, the budget from 2 to [`MAX_MESH_TRIANGLES`] triangles.
    ///
    /// # Errors
    /// [`EngineError::InvalidMesh`] naming the first field out of range.
    pub fn validate(&self) -> Result<(), EngineError> {
        if let Some(e) = self.max_error_m
            && !(e.is_finite() && e >= 0.0)
        {
            let rule = "must be finite and at least 0 metres".to_owned();
            return Err(EngineError::InvalidMesh { field: "max_error_m", value: e.to_string(), rule });
        }
        if !(2..=MAX_MESH_TRIANGLES).contains(&self.max_triangles) {
            let rule = format!("must be from 2 to {MAX_MESH_TRIANGLES}");
            return Err(EngineError::InvalidMesh {
                field: "max_triangles",
                value: self.max_triangles.to_string(),
                rule,
            });
        }
        Ok(())
    }
}

impl TerrainMesh {
    /// The heightfield decimated by greedy insertion ([`relief_tin::approximate`]): the Delaunay
    /// mesh of the fewest samples (within the budget) that keeps every sample within
    /// `options.max_error_m`. No-data samples count as the lowest elevation. Geographic grids are
    /// measured in metres at their middle row.
    ///
    /// # Errors
    /// [`EngineError::NoData`] without a valid sample, [`EngineError::Tin`] for a grid under
    /// 2 × 2 samples, [`EngineError::InvalidMesh`] for options [`MeshOptions::validate`]
    /// refuses.
    pub fn from_heightfield(hf: &Heightfield, options: &MeshOptions) -> Result<Self, EngineError> {
        options.validate()?;
        let (lo, hi) = hf.min_max().ok_or(EngineError::NoData)?;
        let range = f64::from(hi - lo);
        let max_error = options.max_error_m.unwrap_or(range / 1000.0);
        let approx = relief_tin::approximate(hf, &Approximation { max_error, max_triangles: options.max_triangles })?;
        let grid = hf.grid();
        let scale = grid.metres_per_unit(grid.ny() / 2);
        let origin = grid.position(0, 0).min(grid.position(grid.nx() - 1, grid.ny() - 1));
        let mut mesh = Self::from_tin_scaled(&approx.tin, &approx.heights, origin, scale)?;
        mesh.max_error_m = approx.max_error;
        Ok(mesh)
    }

    /// A TIN as it is (coordinates taken as metres, `heights` one per node), relative to the
    /// south-west corner of its bounds.
    ///
    /// # Errors
    /// [`EngineError::Tin`] when `heights` does not match the nodes or holds a non-finite
    /// value.
    pub fn from_tin(tin: &Tin, heights: &[f64]) -> Result<Self, EngineError> {
        let origin = tin.points().iter().fold(DVec2::INFINITY, |m, p| m.min(*p));
        Self::from_tin_scaled(tin, heights, origin, DVec2::ONE)
    }

    fn from_tin_scaled(tin: &Tin, heights: &[f64], origin: DVec2, scale: DVec2) -> Result<Self, EngineError> {
        if heights.len() != tin.num_points() {
            return Err(
                relief_tin::TinError::ValueCountMismatch { expected: tin.num_points(), found: heights.len() }.into()
            );
        }
        if let Some(node) = heights.iter().position(|h| !h.is_finite()) {
            return Err(relief_tin::TinError::NonFiniteValue { node, value: heights[node] }.into());
        }
        let positions = tin.points().iter().zip(heights).map(|(p, &h)| ((*p - origin) * scale).extend(h)).collect();
        Ok(Self { positions, triangles: tin.triangles().to_vec(), origin, max_error_m: 0.0 })
    }

    /// Area-weighted vertex normals, unit length, pointing up.
    pub fn normals(&self) -> Vec<DVec3> {
        let mut n = vec![DVec3::ZERO; self.positions.len()];
        for t in &self.triangles {
            let [a, b, c] = t.map(|v| self.positions[v as usize]);
            let face = (b - a).cross(c - a);
            for &v in t {
                n[v as usize] += face;
            }
        }
        n.into_iter().map(|v| v.try_normalize().unwrap_or(DVec3::Z)).collect()
    }

    /// The glTF 2.0 binary: one node, one mesh, one triangle primitive with `POSITION`, `NORMAL`,
    /// `TEXCOORD_0` (u east, v south, so a north-up image drapes the terrain) and, with
    /// `colours`, `COLOR_0`. glTF is y-up in metres: (x, y, z) = (east, elevation, south).
    ///
    /// # Errors
    /// [`EngineError::Mesh`] for an empty mesh or a glTF the writer refuses.
    pub fn to_glb(&self, colours: bool) -> Result<Vec<u8>, EngineError> {
        if self.triangles.is_empty() {
            return Err(EngineError::Mesh("a mesh without triangles".to_owned()));
        }
        let gltf_frame = |p: DVec3| [p.x as f32, p.z as f32, -p.y as f32];
        let positions: Vec<[f32; 3]> = self.positions.iter().map(|&p| gltf_frame(p)).collect();
        let normals: Vec<[f32; 3]> = self.normals().into_iter().map(gltf_frame).collect();
        let (lo, hi) = self.bounds();
        let size = (hi - lo).truncate().max(DVec2::splat(f64::MIN_POSITIVE));
        let uvs: Vec<[f32; 2]> =
            self.positions.iter().map(|p| [((p.x - lo.x) / size.x) as f32, ((hi.y - p.y) / size.y) as f32]).collect();
        let mut doc = GlbBuilder::default();
        let mut attributes = BTreeMap::new();
        let (pmin, pmax) = (gltf_frame(DVec3::new(lo.x, hi.y, lo.z)), gltf_frame(DVec3::new(hi.x, lo.y, hi.z)));
        attributes.insert(Valid(json::mesh::Semantic::Positions), doc.vertex_f32(&positions, Some((pmin, pmax))));
        attributes.insert(Valid(json::mesh::Semantic::Normals), doc.vertex_f32(&normals, None));
        attributes.insert(Valid(json::mesh::Semantic::TexCoords(0)), doc.vertex_f32(&uvs, None));
        if colours {
            let span = if hi.z > lo.z { hi.z - lo.z } else { 1.0 };
            let rgba: Vec<[u8; 4]> = self
                .positions
                .iter()
                .map(|p| {
                    let [r, g, b] = relief_heightfield_io::hypsometric_tint((p.z - lo.z) / span);
                    [r, g, b, 255.0].map(|c| c.round().clamp(0.0, 255.0) as u8)
                })
                .collect();
            attributes.insert(Valid(json::mesh::Semantic::Colors(0)), doc.colours(&rgba));
        }
        let indices = doc.indices(&self.triangles);
        doc.finish(attributes, indices)
    }

    /// Writes [`TerrainMesh::to_glb`] to `path` atomically.
    ///
    /// # Errors
    /// As [`TerrainMesh::to_glb`], or [`EngineError::Io`].
    pub fn write_glb(&self, path: &Path, colours: bool) -> Result<(), EngineError> {
        relief_heightfield_io::write_atomic(path, &self.to_glb(colours)?)?;
        Ok(())
    }

    /// The lowest and highest corner of the positions' bounding box.
    pub fn bounds(&self) -> (DVec3, DVec3) {
        self.positions.iter().fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), p| (lo.min(*p), hi.max(*p)))
    }
}

/// One binary buffer, its views and accessors.
#[derive(Default)]
struct GlbBuilder {
    root: json::Root,
    bin: Vec<u8>,
}

impl GlbBuilder {
    /// A view of `bytes` (padded to four bytes) for `target`.
    fn view(
        &mut self,
        bytes: &[u8],
        stride: Option<usize>,
        target: json::buffer::Target,
    ) -> json::Index<json::buffer::View> {
        let offset = self.bin.len();
        self.bin.extend_from_slice(bytes);
        self.bin.resize(self.bin.len().next_multiple_of(4), 0);
        self.root.push(json::buffer::View {
            buffer: json::Index::new(0),
            byte_length: USize64::from(bytes.len()),
            byte_offset: Some(USize64::from(offset)),
            byte_stride: stride.map(json::buffer::Stride),
            name: None,
            target: Some(Valid(target)),
            extensions: None,
            extras: json::extras::Void::default(),
        })
    }

    fn accessor(
        &mut self,
        view: json::Index<json::buffer::View>,
        count: usize,
        component: json::accessor::ComponentType,
        type_: json::accessor::Type,
        normalized: bool,
        bounds: Option<(json::Value, json::Value)>,
    ) -> json::Index<json::Accessor> {
        let (min, max) = bounds.unzip();
        self.root.push(json::Accessor {
            buffer_view: Some(view),
            byte_offset: None,
            count: USize64::from(count),
            component_type: Valid(json::accessor::GenericComponentType(component)),
            extensions: None,
            extras: json::extras::Void::default(),
            type_: Valid(type_),
            min,
            max,
            name: None,
            normalized,
            sparse: None,
        })
    }

    /// A float vertex attribute of N components (2 or 3), with min/max when given.
    fn vertex_f32<const N: usize>(
        &mut self,
        values: &[[f32; N]],
        bounds: Option<([f32; N], [f32; N])>,
    ) -> json::Index<json::Accessor> {
        let bytes: Vec<u8> = values.iter().flatten().flat_map(|c| c.to_le_bytes()).collect();
        let view = self.view(&bytes, Some(4 * N), json::buffer::Target::ArrayBuffer);
        let type_ = if N == 2 { json::accessor::Type::Vec2 } else { json::accessor::Type::Vec3 };
        let bounds = bounds.map(|(lo, hi)| (json::Value::from(lo.to_vec()), json::Value::from(hi.to_vec())));
        self.accessor(view, values.len(), json::accessor::ComponentType::F32, type_, false, bounds)
    }

    /// RGBA colours as normalised unsigned bytes (four bytes: every element aligned).
    fn colours(&mut self, rgba: &[[u8; 4]]) -> json::Index<json::Accessor> {
        let bytes: Vec<u8> = rgba.iter().flatten().copied().collect();
        let view = self.view(&bytes, Some(4), json::buffer::Target::ArrayBuffer);
        self.accessor(view, rgba.len(), json::accessor::ComponentType::U8, json::accessor::Type::Vec4, true, None)
    }

    fn indices(&mut self, triangles: &[[u32; 3]]) -> json::Index<json::Accessor> {
        let bytes: Vec<u8> = triangles.iter().flatten().flat_map(|v| v.to_le_bytes()).collect();
        let view = self.view(&bytes, None, json::buffer::Target::ElementArrayBuffer);
        let count = 3 * triangles.len();
        self.accessor(view, count, json::accessor::ComponentType::U32, json::accessor::Type::Scalar, false, None)
    }

    /// The scene around one primitive, a matte material, and the GLB container.
    fn finish(
        mut self,
        attributes: BTreeMap<json::validation::Checked<json::mesh::Semantic>, json::Index<json::Accessor>>,
        indices: json::Index<json::Accessor>,
    ) -> Result<Vec<u8>, EngineError> {
        self.root.asset.generator = Some(format!("relief {}", env!("CARGO_PKG_VERSION")));
        self.root.push(json::Buffer {
            byte_length: USize64::from(self.bin.len()),
            name: None,
            uri: None,
            extensions: None,
            extras: json::extras::Void::default(),
        });
        let material = self.root.push(json::Material {
            name: Some("terrain".to_owned()),
            pbr_metallic_roughness: json::material::PbrMetallicRoughness {
                metallic_factor: json::material::StrengthFactor(0.0),
                roughness_factor: json::material::StrengthFactor(1.0),
                ..Default::default()
            },
            ..Default::default()
        });
        let primitive = json::mesh::Primitive {
            attributes,
            extensions: None,
            extras: json::extras::Void::default(),
            indices: Some(indices),
            material: Some(material),
            mode: Valid(json::mesh::Mode::Triangles),
            targets: None,
        };
        let mesh = self.root.push(json::Mesh {
            extensions: None,
            extras: json::extras::Void::default(),
            name: Some("terrain".to_owned()),
            primitives: vec![primitive],
            weights: None,
        });
        let node =
            self.root.push(json::Node { mesh: Some(mesh), name: Some("terrain".to_owned()), ..Default::default() });
        let scene = self.root.push(json::Scene {
            extensions: None,
            extras: json::extras::Void::default(),
            name: None,
            nodes: vec![node],
        });
        self.root.scene = Some(scene);
        let text = json::serialize::to_vec(&self.root).map_err(|e| EngineError::Mesh(e.to_string()))?;
        let glb = gltf::binary::Glb {
            header: gltf::binary::Header { magic: *b"glTF", version: 2, length: 0 },
            json: Cow::Owned(text),
            bin: Some(Cow::Owned(self.bin)),
        };
        glb.to_vec().map_err(|e| EngineError::Mesh(e.to_string()))
    }
}
