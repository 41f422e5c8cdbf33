//! The spacetime threshold of Algorithm 1 as a WGSL compute kernel
//! (`shaders/spacetime_threshold.wgsl`), launched on the device Burn's wgpu backend already
//! holds (Vulkan natively, WebGPU in the browser). The decoder's edge embeddings stay on the
//! device; only a bit matrix of edges comes back, and [`crate::extract::edges_from_bits`] turns
//! it into the edge list. Faces, hole repair and winding stay in Rust on the host.

use burn::tensor::{DType, Int, Tensor};
use burn_cubecl::cubecl::ir::{UIntKind, metadata::Info};
use burn_cubecl::cubecl::prelude::*;
use burn_cubecl::cubecl::server::KernelArguments;
use burn_cubecl::cubecl::{CubeKernel, PrecompiledSource};
use burn_cubecl::{Cube, kernel::into_contiguous, tensor::CubeTensor};

/// The kernel's text; it is part of the binary, so its type identifies it.
const SOURCE: &str = include_str!("../../../shaders/spacetime_threshold.wgsl");
/// `@workgroup_size` in [`SOURCE`].
const WORKGROUP: u32 = 64;
/// WebGPU's guaranteed `maxComputeWorkgroupsPerDimension`.
const MAX_GROUPS: u32 = 65_535;

/// Why the GPU threshold cannot run on these tensors; callers fall back to the CPU kernel.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GpuThresholdError {
    #[error("the tensors are not on a wgpu device")]
    NotOnWgpu,
    #[error(
        "edge embeddings must be [B, N, even dim] and mask logits [B, N, 1]; got {} and {}",
        crate::shape_text(.0),
        crate::shape_text(.1)
    )]
    Shapes(Vec<usize>, Vec<usize>),
    #[error("{0} words do not fit one dispatch")]
    TooLarge(usize),
}

/// u32 words per row of the bit matrix for `n` vertices.
pub fn words_per_row(n: usize) -> usize {
    n.div_ceil(32)
}

/// Thresholds decoded edge embeddings `[B, N, E]` (E even) against `tau` for the vertices whose
/// mask logit `[B, N, 1]` is > 0, on their wgpu device. Returns the `[B, N, ceil(N / 32)]` u32
/// bit matrix described in the shader (and in [`crate::extract::edges_from_bits`]), still on
/// the device: read it back with `into_data` or `into_data_async`.
pub fn spacetime_edge_bits(
    edge_embeddings: Tensor<3>,
    mask_logits: Tensor<3>,
    tau: f32,
) -> Result<Tensor<3, Int>, GpuThresholdError> {
    let ([b, n, e], mask) = (edge_embeddings.dims(), mask_logits.dims());
    if e % 2 != 0 || mask != [b, n, 1] {
        return Err(GpuThresholdError::Shapes(vec![b, n, e], mask.to_vec()));
    }
    let words = words_per_row(n);
    let total = b * n * words;
    let groups = total.div_ceil(WORKGROUP as usize);
    let (gx, gy) = if groups <= MAX_GROUPS as usize {
        (groups as u32, 1)
    } else {
        (MAX_GROUPS, groups.div_ceil(MAX_GROUPS as usize) as u32)
    };
    if gy > MAX_GROUPS {
        return Err(GpuThresholdError::TooLarge(total));
    }
    let cube = |t: Tensor<3>| -> Result<CubeTensor, GpuThresholdError> {
        // The kernel indexes rows directly, so the buffers must be dense and row-major.
        let t = into_contiguous(
            t.try_into_primitive::<Cube>()
                .map_err(|_| GpuThresholdError::NotOnWgpu)?,
        );
        if t.dtype != DType::F32 {
            return Err(GpuThresholdError::NotOnWgpu);
        }
        Ok(t)
    };
    let embeddings = cube(edge_embeddings)?;
    let mask = cube(mask_logits)?;
    let client = embeddings.client.clone();

    let mut params = [b as u32, n as u32, e as u32, words as u32, 0];
    params[4] = tau.to_bits();
    let params = client.create_from_slice(u32_bytes(&params));
    let bits = client.empty(total.max(1) * 4);
    client.launch(
        Box::new(ThresholdKernel),
        CubeCount::Static(gx, gy, 1),
        KernelArguments::new()
            .with_buffer(embeddings.handle.clone().binding())
            .with_buffer(mask.handle.clone().binding())
            .with_buffer(bits.clone().binding())
            .with_buffer(params.binding()),
    );
    let bits = CubeTensor::new_contiguous(
        client,
        embeddings.device.clone(),
        [b, n, words].into(),
        bits,
        DType::U32,
    );
    Ok(Tensor::from_primitive::<Cube>(bits))
}

fn u32_bytes(words: &[u32]) -> &[u8] {
    // SAFETY: u32 has no padding and any byte pattern is a valid u8.
    unsafe { std::slice::from_raw_parts(words.as_ptr().cast(), std::mem::size_of_val(words)) }
}

/// The WGSL kernel as cubecl sees it: no IR to compile, its own text instead.
struct ThresholdKernel;

impl KernelMetadata for ThresholdKernel {
    fn id(&self) -> KernelId {
        KernelId::new::<Self>()
    }

    fn address_type(&self) -> ElemType {
        ElemType::UInt(UIntKind::U32)
    }
}

impl CubeKernel for ThresholdKernel {
    fn define(&self) -> KernelDefinition {
        let settings = KernelSettings::new(
            CubeDim::new_1d(WORKGROUP).0,
            ExecutionMode::Checked,
            AddressType::U32,
        );
        KernelDefinition {
            body: Scope::root(settings.clone()),
            settings,
            info: Info::default(),
        }
    }

    fn source(&self) -> Option<PrecompiledSource> {
        Some(PrecompiledSource {
            source: SOURCE.to_string(),
            entrypoint_name: "main".to_string(),
            lang: "wgsl",
        })
    }
}
