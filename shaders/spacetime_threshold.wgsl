// The spacetime threshold of MeshFlow's Algorithm 1 (docs/design.md section 2), on the GPU.
//
// Vertices i < j of one decoded mesh are joined iff both are kept (mask logit > 0) and
//   d(h_i, h_j) = |s_i - s_j|^2 - |t_i - t_j|^2 > tau,
// where s is the first half of the edge embedding h and t the second half.
//
// The answer is a bit matrix, one row of `words` u32 words per vertex: bit (j % 32) of word
// (b * n + i) * words + j / 32 is set iff (i, j) is an edge of mesh b. Only these bits go back
// to the host (32 KiB for n = 512, where the embeddings are 64 KiB and the distances 1 MiB), and
// the host turns them into the edge list (crate/src/extract/mod.rs, `edges_from_bits`).
//
// One invocation writes one word: 32 candidate pairs of one row, so no atomics are needed and
// the result does not depend on scheduling. The distance is summed directly (not through the
// Gram expansion the CPU kernel uses), in the order k = 0, 1, ..., which keeps it within a few
// ulps of the CPU value; pairs that close to tau may differ between the two.

struct Params {
    batch: u32,
    n: u32,
    // Embedding channels per vertex (even).
    dim: u32,
    // u32 words per row: ceil(n / 32).
    words: u32,
    tau: f32,
}

// Every binding is read_write although only `bits` is written: Burn's allocator sub-allocates
// tensors from shared wgpu buffers, and a dispatch may not use one buffer both read-only and
// read-write.
// [batch, n, dim], row-major.
@group(0) @binding(0) var<storage, read_write> embeddings: array<f32>;
// [batch, n], one logit per vertex.
@group(0) @binding(1) var<storage, read_write> mask_logits: array<f32>;
// [batch, n, words].
@group(0) @binding(2) var<storage, read_write> bits: array<u32>;
@group(0) @binding(3) var<storage, read_write> params: Params;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    // A 2-D grid when one dimension would exceed the dispatch limit.
    let word = gid.y * groups.x * 64u + gid.x;
    let total = params.batch * params.n * params.words;
    if (word >= total) {
        return;
    }
    let row = word / params.words; // b * n + i
    let i = row % params.n;
    let first = (word % params.words) * 32u;
    let mesh = row - i; // b * n
    let half = params.dim / 2u;
    let base_i = row * params.dim;

    var out = 0u;
    if (mask_logits[row] > 0.0) {
        for (var c = 0u; c < 32u; c = c + 1u) {
            let j = first + c;
            if (j <= i || j >= params.n) {
                continue;
            }
            if (!(mask_logits[mesh + j] > 0.0)) {
                continue;
            }
            let base_j = (mesh + j) * params.dim;
            var space = 0.0;
            for (var k = 0u; k < half; k = k + 1u) {
                let diff = embeddings[base_i + k] - embeddings[base_j + k];
                space = space + diff * diff;
            }
            var time = 0.0;
            for (var k = half; k < params.dim; k = k + 1u) {
                let diff = embeddings[base_i + k] - embeddings[base_j + k];
                time = time + diff * diff;
            }
            if (space - time > params.tau) {
                out = out | (1u << c);
            }
        }
    }
    bits[word] = out;
}
