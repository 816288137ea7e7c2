//! The structured input of the `dent_api` target: meshes picked from a small set, numbers that
//! are often in a useful range and sometimes anything (NaN, ±∞, huge), and the call to make.
//!
//! Values the library would accept but that only cost time (a 2048² grid, 100,000 smoothing
//! steps) are shrunk to small valid ones; invalid values are passed through unchanged, so their
//! refusal is still exercised.

use std::sync::OnceLock;

use arbitrary::Arbitrary;
use dentbend::glam::Vec3;
use dentbend::mesh::{self, TriMesh};
use dentbend::dent::Refine;
use dentbend::{Attenuation, DentParams, Resolution, VolumeMode};

/// Largest grid side the fuzzer lets through, cells.
const MAX_FUZZ_RES: u32 = 48;
/// Largest smoothing step count the fuzzer lets through.
const MAX_FUZZ_ITERS: u32 = 40;

/// A number: mostly in a range that dents, sometimes special or arbitrary bits.
#[derive(Arbitrary, Debug, Clone, Copy)]
pub enum Num {
    /// `n / 256`, in [0, 256).
    Small(u16),
    /// `−n / 256`.
    Negative(u16),
    /// Any f32 bit pattern.
    Bits(u32),
    Nan,
    Infinity,
    NegInfinity,
    Max,
    TinyPositive,
    Zero,
}

impl Num {
    /// The f32 it stands for.
    pub fn value(self) -> f32 {
        match self {
            Self::Small(n) => f32::from(n) / 256.0,
            Self::Negative(n) => -f32::from(n) / 256.0,
            Self::Bits(b) => f32::from_bits(b),
            Self::Nan => f32::NAN,
            Self::Infinity => f32::INFINITY,
            Self::NegInfinity => f32::NEG_INFINITY,
            Self::Max => f32::MAX,
            Self::TinyPositive => f32::MIN_POSITIVE,
            Self::Zero => 0.0,
        }
    }
}

/// Three numbers.
#[derive(Arbitrary, Debug, Clone, Copy)]
pub struct Vector(pub Num, pub Num, pub Num);

impl Vector {
    /// The vector it stands for.
    pub fn vec3(self) -> Vec3 {
        Vec3::new(self.0.value(), self.1.value(), self.2.value())
    }
}

/// A small mesh.
#[derive(Arbitrary, Debug, Clone, Copy)]
pub enum Shape {
    /// Built-in `box` (2 m cube, 3,072 triangles).
    BuiltinBox,
    /// Built-in `sphere` (radius 1, 5,120 triangles).
    BuiltinSphere,
    /// Icosphere of radius 0.3 m, 80 triangles.
    SmallBall,
    /// A 2 m cube of 12 triangles.
    CoarseBox,
    /// One triangle (an open surface).
    Triangle,
    /// A tetrahedron.
    Tetrahedron,
}

impl Shape {
    /// The mesh (built once per process, cloned per use).
    pub fn mesh(self) -> TriMesh {
        static MESHES: OnceLock<Vec<TriMesh>> = OnceLock::new();
        let meshes = MESHES.get_or_init(|| {
            let triangle = vec![Vec3::ZERO, Vec3::X, Vec3::Z];
            let tetrahedron = vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z];
            vec![
                mesh::builtin("box").expect("built-in box"),
                mesh::builtin("sphere").expect("built-in sphere"),
                mesh::icosphere(0.3, 1).expect("icosphere"),
                mesh::subdivided_box(Vec3::splat(2.0), [1; 3]).expect("box"),
                TriMesh::new(triangle, vec![[0, 2, 1]]).expect("triangle"),
                TriMesh::new(tetrahedron, vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]).expect("tetrahedron"),
            ]
        });
        meshes[self as usize].clone()
    }
}

/// The grid side choice.
#[derive(Arbitrary, Debug, Clone, Copy)]
pub enum ResolutionInput {
    Auto { min: u32, max: u32 },
    Fixed(u32),
    Default,
}

/// The falloff choice; the custom ones are fixed functions, well and badly behaved.
#[derive(Arbitrary, Debug, Clone, Copy)]
pub enum AttenuationInput {
    Logistic,
    Linear(Num),
    None,
    /// `a = 1` everywhere (valid).
    CustomOne,
    /// NaN below the surface.
    CustomNan,
    /// `a(0) = 2` (refused).
    CustomWrongAtZero,
    /// Grows without bound with depth.
    CustomExploding,
}

/// The refine stage's setting; valid edges are kept at or above 0.05 (a fine edge only costs
/// time, up to the library's cap of a million new triangles).
#[derive(Arbitrary, Debug, Clone, Copy)]
pub enum RefineInput {
    Auto(u16),
    Off,
    MaxEdge(Num),
}

/// Every field of [`DentParams`].
#[derive(Arbitrary, Debug, Clone)]
pub struct ParamsInput {
    pub dent_distance: Num,
    pub sigma: Option<Num>,
    pub resolution: ResolutionInput,
    pub heat_iters: u32,
    pub clamp_iters: u32,
    pub heat_rate: Num,
    pub attenuation: AttenuationInput,
    pub widen: Num,
    pub min_cos: Num,
    pub refine: RefineInput,
    pub preserve_volume: bool,
    pub guard_crossings: bool,
}

/// `n` shrunk into 1..=`MAX_FUZZ_RES` when the library would accept it, else as is.
fn cheap_res(n: u32) -> u32 {
    if (1..=dentbend::dent::MAX_RESOLUTION).contains(&n) { 1 + (n - 1) % MAX_FUZZ_RES } else { n }
}

/// A step count shrunk below `MAX_FUZZ_ITERS` when the library would accept it, else as is.
fn cheap_iters(n: u32) -> u32 {
    if n <= 100_000 { n % MAX_FUZZ_ITERS } else { n }
}

impl ParamsInput {
    /// The parameters it stands for.
    pub fn params(&self) -> DentParams {
        let resolution = match self.resolution {
            ResolutionInput::Default => Resolution::Auto { min: 8, max: MAX_FUZZ_RES },
            ResolutionInput::Fixed(n) => Resolution::Fixed(cheap_res(n)),
            ResolutionInput::Auto { min, max } => {
                let valid = min >= 1 && min <= max && max <= dentbend::dent::MAX_RESOLUTION;
                if valid {
                    let min = cheap_res(min);
                    Resolution::Auto { min, max: min.max(cheap_res(max)) }
                } else {
                    Resolution::Auto { min, max }
                }
            }
        };
        let attenuation = match self.attenuation {
            AttenuationInput::Logistic => Attenuation::Logistic,
            AttenuationInput::Linear(scale) => Attenuation::Linear { scale: scale.value() },
            AttenuationInput::None => Attenuation::None,
            AttenuationInput::CustomOne => Attenuation::Custom(std::sync::Arc::new(|_, _| 1.0)),
            AttenuationInput::CustomNan => {
                Attenuation::Custom(std::sync::Arc::new(|z, _| if z > 0.0 { f32::NAN } else { 1.0 }))
            }
            AttenuationInput::CustomWrongAtZero => Attenuation::Custom(std::sync::Arc::new(|_, _| 2.0)),
            AttenuationInput::CustomExploding => Attenuation::Custom(std::sync::Arc::new(|z, d| (z / d).exp())),
        };
        DentParams {
            dent_distance: self.dent_distance.value(),
            sigma: self.sigma.map(Num::value),
            resolution,
            heat_iters: cheap_iters(self.heat_iters),
            clamp_iters: cheap_iters(self.clamp_iters),
            heat_rate: self.heat_rate.value(),
            attenuation,
            widen: self.widen.value(),
            min_cos: self.min_cos.value(),
            refine: match self.refine {
                RefineInput::Auto(cap) => Refine::Auto { max_new_triangles: u32::from(cap) },
                RefineInput::Off => Refine::Off,
                RefineInput::MaxEdge(edge) => {
                    let edge = edge.value();
                    Refine::MaxEdge(if edge.is_finite() && edge > 0.0 { edge.max(0.05) } else { edge })
                }
            },
            volume: if self.preserve_volume { VolumeMode::Preserve } else { VolumeMode::Free },
            guard_crossings: self.guard_crossings,
        }
    }
}

/// Which API call to make.
#[derive(Arbitrary, Debug, Clone)]
pub enum Call {
    /// `dent(target, projectile, …)`.
    Dent,
    /// `dent_pair(target, projectile, …)` with the projectile's own parameters, or the target's
    /// when `None` (the paper's Figure 1 case, and far likelier to succeed).
    DentPair { other: Option<ParamsInput> },
    /// `DentMap::gaussian(width, …)` applied to the target.
    Gaussian { width: Num },
    /// `DentMap::from_heights` on a `res × res` grid (heights repeated to fill it) applied to
    /// the target.
    Heights { res: u8, extent: Num, heights: Vec<Num> },
    /// `decide_dent_distance` for a fixed target and a moving projectile.
    Decide { threshold: Num, gain: Num, cap: Num, hardness: Option<Num>, mass: Num, spin: Vector },
}

/// One execution's input.
#[derive(Arbitrary, Debug, Clone)]
pub struct DentInput {
    pub target: Shape,
    pub projectile: Shape,
    /// Where the projectile is moved to, m.
    pub projectile_offset: Vector,
    pub point: Vector,
    pub normal: Vector,
    pub relative_velocity: Vector,
    pub params: ParamsInput,
    pub call: Call,
}
