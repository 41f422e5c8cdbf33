//! Weights in safetensors under the reference's state-dict names.
//!
//! A module's parameter path (Burn's field names, e.g. `encoder.blocks.0.attn1.to_out.weight`)
//! becomes the reference name by [`reference_component`] applied to each component
//! (`to_out` -> `to_out.0`, ...). Linear weights are `[in, out]` in Burn and `[out, in]` in the
//! reference's files; they are transposed on the host here, never on the device (Burn's
//! column layout transposes through a blocking device sync, which the browser cannot do).
//! Loading checks every name and shape without initialising the module's random weights, and
//! refuses a file that does not match the module exactly.

use std::collections::{BTreeMap, BTreeSet};

use burn::module::{Module, ModuleMapper, ModuleVisitor, Param};
use burn::tensor::{Device, Tensor, TensorData};
use safetensors::{Dtype, SafeTensors};

/// Why a weights file was refused.
#[derive(Debug, thiserror::Error)]
pub enum WeightsError {
    #[error("not a safetensors file: {0}")]
    Format(String),
    #[error("tensor {name}: dtype {dtype} is not supported (only F32, F64 and F16)")]
    Dtype { name: String, dtype: String },
    #[error(
        "tensor {name}: shape {} does not match the configuration's {}",
        crate::shape_text(.found),
        crate::shape_text(.expected)
    )]
    Shape {
        name: String,
        expected: Vec<usize>,
        found: Vec<usize>,
    },
    #[error("{} tensor(s) missing from the weights file, e.g. {}", .0.len(), .0[0])]
    Missing(Vec<String>),
    #[error("{} tensor(s) in the weights file that the configuration has no place for, e.g. {}", .0.len(), .0[0])]
    Unexpected(Vec<String>),
    #[error("invalid configuration: {0}")]
    Config(String),
    #[error("{0}")]
    Io(String),
}

/// Named f32 tensors (row-major) in a stable order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TensorMap {
    pub tensors: BTreeMap<String, (Vec<usize>, Vec<f32>)>,
}

impl TensorMap {
    /// Reads the tensors of a safetensors file whose names start with `prefix`, with the prefix
    /// removed (`""` reads all). F32 and F16 tensors are read exactly and F64 ones rounded to
    /// F32; other dtypes are refused.
    pub fn from_safetensors(bytes: &[u8], prefix: &str) -> Result<Self, WeightsError> {
        Self::read(bytes, prefix, false)
    }

    /// All tensors of a test-vector file as f32: F32, F64 and I64 (indices) converted, other
    /// dtypes skipped.
    pub fn floats_of_safetensors(bytes: &[u8]) -> Result<Self, WeightsError> {
        Self::read(bytes, "", true)
    }

    fn read(bytes: &[u8], prefix: &str, skip_non_float: bool) -> Result<Self, WeightsError> {
        let st =
            SafeTensors::deserialize(bytes).map_err(|e| WeightsError::Format(e.to_string()))?;
        let mut tensors = BTreeMap::new();
        for (name, view) in st.tensors() {
            let Some(short) = name.strip_prefix(prefix) else {
                continue;
            };
            if skip_non_float && !matches!(view.dtype(), Dtype::F32 | Dtype::F64 | Dtype::I64) {
                continue;
            }
            let values = match view.dtype() {
                Dtype::F32 => view
                    .data()
                    .chunks_exact(4)
                    .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
                    .collect(),
                Dtype::I64 if skip_non_float => view
                    .data()
                    .chunks_exact(8)
                    .map(|c| i64::from_le_bytes(c.try_into().expect("8 bytes")) as f32)
                    .collect(),
                Dtype::F64 => view
                    .data()
                    .chunks_exact(8)
                    .map(|c| f64::from_le_bytes(c.try_into().expect("8 bytes")) as f32)
                    .collect(),
                // Half-size weights for the browser download (exactly representable in f32).
                Dtype::F16 => view
                    .data()
                    .chunks_exact(2)
                    .map(|c| half::f16::from_le_bytes([c[0], c[1]]).to_f32())
                    .collect(),
                other => {
                    return Err(WeightsError::Dtype {
                        name,
                        dtype: other.to_string(),
                    });
                }
            };
            tensors.insert(short.to_string(), (view.shape().to_vec(), values));
        }
        Ok(Self { tensors })
    }

    /// Serialises to safetensors (names sorted, so the bytes are deterministic).
    pub fn to_safetensors(&self, metadata: Option<BTreeMap<String, String>>) -> Vec<u8> {
        let bytes: Vec<(String, Vec<usize>, Vec<u8>)> = self
            .tensors
            .iter()
            .map(|(name, (shape, values))| {
                let raw = values.iter().flat_map(|v| v.to_le_bytes()).collect();
                (name.clone(), shape.clone(), raw)
            })
            .collect();
        let views: Vec<(String, safetensors::tensor::TensorView<'_>)> = bytes
            .iter()
            .map(|(name, shape, raw)| {
                let view = safetensors::tensor::TensorView::new(Dtype::F32, shape.clone(), raw)
                    .expect("shape and byte length agree by construction");
                (name.clone(), view)
            })
            .collect();
        let metadata = metadata.map(|m| m.into_iter().collect());
        safetensors::serialize(views, metadata).expect("in-memory serialisation cannot fail")
    }

    /// The tensor called `name` on `device`.
    pub fn tensor<const D: usize>(&self, name: &str, device: &Device) -> Option<Tensor<D>> {
        let (shape, values) = self.tensors.get(name)?;
        (shape.len() == D)
            .then(|| Tensor::from_data(TensorData::new(values.clone(), shape.clone()), device))
    }
}

/// Reference name of one component of a Burn module path; the rest are the same in both.
/// The VAE and the DiT share one [`crate::model::layers::Attention`], whose reference names
/// differ: `in_dit` gives the DiT's (`q_norm`, `k_norm`, `out_proj` for the VAE's `norm_q`,
/// `norm_k`, `to_out.0`).
pub fn reference_component(component: &str, in_dit: bool) -> &str {
    match (component, in_dit) {
        ("norm_q", true) => "q_norm",
        ("norm_k", true) => "k_norm",
        ("to_out", true) => "out_proj",
        ("to_out", false) => "to_out.0",
        ("linear_in", _) => "net.0.proj",
        ("linear_out", _) => "net.2",
        ("hidden", _) => "0",
        ("output", _) => "2",
        ("gamma", _) => "weight",
        ("beta", _) => "bias",
        ("adaln", _) => "adaLN_modulation.1",
        // The DiT's optional long-skip module: its tensors sit directly in the block.
        ("skip", _) => "",
        (other, _) => other,
    }
}

/// The reference name of a Burn module path.
pub fn reference_name(path: &[String]) -> String {
    // The DiT's blocks are its top-level `blocks`; the VAE's sit under `encoder`/`decoder`.
    let in_dit = path.first().is_some_and(|c| c == "blocks");
    path.iter()
        .map(|c| reference_component(c, in_dit))
        .filter(|c| !c.is_empty())
        .collect::<Vec<_>>()
        .join(".")
}

/// `values` (row-major `[rows, cols]`) transposed to `[cols, rows]`.
fn transpose(values: &[f32], rows: usize, cols: usize) -> Vec<f32> {
    let mut out = vec![0.0; values.len()];
    for r in 0..rows {
        for c in 0..cols {
            out[c * rows + r] = values[r * cols + c];
        }
    }
    out
}

/// The module path of a parameter, and whether it is a Linear weight (stored transposed).
#[derive(Default)]
struct ModulePath {
    names: Vec<String>,
    containers: Vec<String>,
}

impl ModulePath {
    fn enter(&mut self, name: &str, container: &str) {
        self.names.push(name.to_string());
        self.containers.push(container.to_string());
    }

    fn exit(&mut self) {
        self.names.pop();
        self.containers.pop();
    }

    /// Burn names a field's container `Struct:<type>`: a Linear's `weight` field.
    fn is_linear_weight(&self, rank: usize) -> bool {
        rank == 2
            && self.names.last().is_some_and(|l| l == "weight")
            && self.containers.last().is_some_and(|c| c == "Struct:Linear")
    }
}

struct Loader<'a> {
    path: ModulePath,
    map: &'a TensorMap,
    used: BTreeSet<String>,
    missing: Vec<String>,
    error: Option<WeightsError>,
}

impl ModuleMapper for Loader<'_> {
    fn enter_module(&mut self, name: &str, container: &str) {
        self.path.enter(name, container);
    }

    fn exit_module(&mut self, _name: &str, _container: &str) {
        self.path.exit();
    }

    fn map_float<const D: usize>(&mut self, param: Param<Tensor<D>>) -> Param<Tensor<D>> {
        let name = reference_name(&self.path.names);
        let Some((shape, values)) = self.map.tensors.get(&name) else {
            self.missing.push(name);
            return param;
        };
        self.used.insert(name.clone());
        // The shape the reference stores; read without initialising the parameter.
        let dims = param.lazy_shape().to_vec();
        let linear = self.path.is_linear_weight(D);
        let expected: Vec<usize> = if linear {
            dims.iter().rev().copied().collect()
        } else {
            dims.clone()
        };
        if *shape != expected {
            self.error.get_or_insert(WeightsError::Shape {
                name,
                expected,
                found: shape.clone(),
            });
            return param;
        }
        let values = if linear {
            transpose(values, shape[0], shape[1])
        } else {
            values.clone()
        };
        let tensor = Tensor::<D>::from_data(TensorData::new(values, dims), &param.lazy_device());
        let id = param.id;
        param.transform_for_load(tensor, id)
    }
}

/// Loads `map` into `module`. Every parameter must be present with its exact shape, and every
/// tensor in `map` must be used, except names for which `ignore` returns true.
pub fn load_module<M: Module>(
    module: M,
    map: &TensorMap,
    ignore: &dyn Fn(&str) -> bool,
) -> Result<M, WeightsError> {
    load_module_keeping(module, map, ignore, &|_| false)
}

/// [`load_module`], except that parameters for which `keep` returns true may be absent from
/// `map`: those keep the values `module` already has (its initialisation).
pub fn load_module_keeping<M: Module>(
    module: M,
    map: &TensorMap,
    ignore: &dyn Fn(&str) -> bool,
    keep: &dyn Fn(&str) -> bool,
) -> Result<M, WeightsError> {
    let mut loader = Loader {
        path: ModulePath::default(),
        map,
        used: BTreeSet::new(),
        missing: Vec::new(),
        error: None,
    };
    let module = module.map(&mut loader);
    if let Some(e) = loader.error {
        return Err(e);
    }
    loader.missing.retain(|name| !keep(name));
    if !loader.missing.is_empty() {
        return Err(WeightsError::Missing(loader.missing));
    }
    let unexpected: Vec<String> = map
        .tensors
        .keys()
        .filter(|k| !loader.used.contains(*k) && !ignore(k))
        .cloned()
        .collect();
    if !unexpected.is_empty() {
        return Err(WeightsError::Unexpected(unexpected));
    }
    Ok(module)
}

struct Collector {
    path: ModulePath,
    map: TensorMap,
}

impl ModuleVisitor for Collector {
    fn enter_module(&mut self, name: &str, container: &str) {
        self.path.enter(name, container);
    }

    fn exit_module(&mut self, _name: &str, _container: &str) {
        self.path.exit();
    }

    fn visit_float<const D: usize>(&mut self, param: &Param<Tensor<D>>) {
        let tensor = param.transform_for_save().val();
        let mut shape = tensor.dims().to_vec();
        let mut values = tensor
            .try_into_data()
            .expect("reading back a parameter")
            .convert::<f32>()
            .try_into_vec::<f32>()
            .expect("f32 data");
        if self.path.is_linear_weight(D) {
            values = transpose(&values, shape[0], shape[1]);
            shape.reverse();
        }
        self.map
            .tensors
            .insert(reference_name(&self.path.names), (shape, values));
    }
}

/// All parameters of `module` under their reference names.
pub fn module_tensors<M: Module>(module: &M) -> TensorMap {
    let mut collector = Collector {
        path: ModulePath::default(),
        map: TensorMap::default(),
    };
    module.visit(&mut collector);
    collector.map
}

struct SeededInit {
    path: Vec<String>,
    rng: crate::rng::Rng,
    fan_in: usize,
}

impl ModuleMapper for SeededInit {
    fn enter_module(&mut self, name: &str, _container: &str) {
        self.path.push(name.to_string());
    }

    fn exit_module(&mut self, _name: &str, _container: &str) {
        self.path.pop();
    }

    fn map_float<const D: usize>(&mut self, param: Param<Tensor<D>>) -> Param<Tensor<D>> {
        let dims = param.lazy_shape().to_vec();
        let device = param.lazy_device();
        let n = dims.iter().product::<usize>();
        let last = self.path.last().map(String::as_str).unwrap_or("");
        // A decoder's vertex block starts as the identity (VaeConfig::num_layers_vertex): its
        // two residual branches end in zero projections; a pair head's correction starts at 0.
        let parent = self
            .path
            .len()
            .checked_sub(2)
            .map(|i| self.path[i].as_str());
        let zero_output = (self.path.iter().any(|p| p == "vertex_blocks")
            && matches!(parent, Some("to_out" | "linear_out")))
            || (self.path.iter().any(|p| p == "pair_head") && parent == Some("output"));
        let values: Vec<f32> = match (last, D) {
            _ if zero_output => vec![0.0; n],
            ("gamma", _) => vec![1.0; n],
            ("beta", _) => vec![0.0; n],
            ("skip_gate", _) => vec![0.5; n],
            (_, 2) => {
                // Linear weights are stored [in, out]: PyTorch's default bound 1/sqrt(fan_in).
                self.fan_in = dims[0];
                let bound = 1.0 / (self.fan_in as f64).sqrt();
                (0..n)
                    .map(|_| ((2.0 * self.rng.next_f64() - 1.0) * bound) as f32)
                    .collect()
            }
            _ => {
                // A bias: the bound of the weight before it in the same Linear.
                let bound = 1.0 / (self.fan_in.max(1) as f64).sqrt();
                (0..n)
                    .map(|_| ((2.0 * self.rng.next_f64() - 1.0) * bound) as f32)
                    .collect()
            }
        };
        let id = param.id;
        param.transform_for_load(
            Tensor::<D>::from_data(TensorData::new(values, dims), &device),
            id,
        )
    }
}

/// Re-initialises every parameter from a seeded generator, PyTorch-style (Linear weights and
/// biases uniform in +-1/sqrt(fan_in), norm scales 1 and shifts 0, skip gates 0.5), so a
/// training run starts from the same weights on every backend and in every process.
pub fn seeded_init<M: Module>(module: M, seed: u64) -> M {
    let mut init = SeededInit {
        path: Vec::new(),
        rng: crate::rng::Rng::new(seed),
        fan_in: 1,
    };
    module.map(&mut init)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// F16 tensors (the browser's half-size weights) read back as the f32 values they hold.
    #[test]
    fn f16_tensors_read_as_their_exact_values() {
        let values = [0.0f32, 1.0, -2.5, 0.333_251_95, 65504.0, 6.1035156e-5];
        let raw: Vec<u8> = values
            .iter()
            .flat_map(|&v| half::f16::from_f32(v).to_le_bytes())
            .collect();
        let view = safetensors::tensor::TensorView::new(Dtype::F16, vec![2, 3], &raw).unwrap();
        let bytes = safetensors::serialize([("w".to_string(), view)], None).unwrap();
        let map = TensorMap::from_safetensors(&bytes, "").unwrap();
        assert_eq!(map.tensors["w"], (vec![2, 3], values.to_vec()));
    }
}
