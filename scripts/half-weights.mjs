// Half-size weights: `node scripts/half-weights.mjs [SRC] [DST]` (default weights/ in place)
// rewrites vae.safetensors and dit.safetensors of SRC (each one that is there) with every F32
// tensor rounded to F16 (round to nearest, ties to even) into DST, and their manifests with
// the new sha256 (`converted_from_sha256` keeps the original's; a DiT trained on the VAE
// converted in the same call names the new VAE file). A file already in F16 is left as it is.
// Every surface runs these (the CLI, the crate's tests, the page and the npm package), so one
// file gives one mesh everywhere; test-split generation with F16 is within noise of F32 over
// two seeds (docs/experiments/2026-12-02-f16-weights.md). Training writes F32; its ship step
// runs this. The Rust loader reads F16 exactly (crate/src/model/weights.rs).
import { createHash } from 'node:crypto';
import { existsSync, mkdirSync, readFileSync, renameSync, writeFileSync } from 'node:fs';
import { join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';

const ROOT = resolve(fileURLToPath(new URL('..', import.meta.url)));
const src = resolve(process.argv[2] ?? join(ROOT, 'weights'));
const dst = resolve(process.argv[3] ?? src);

const word = new Float32Array(1);
const bits = new Uint32Array(word.buffer);

/** The IEEE binary16 bits nearest to `value` (ties to even; overflow to infinity). */
export function halfBits(value) {
  word[0] = value;
  const x = bits[0];
  const sign = (x >>> 16) & 0x8000;
  const exponent = (x >>> 23) & 0xff;
  let mantissa = x & 0x7fffff;
  if (exponent === 0xff) return sign | 0x7c00 | (mantissa ? 0x200 : 0);
  const e = exponent - 127 + 15;
  if (e >= 0x1f) return sign | 0x7c00;
  let shift = 13;
  let base = e << 10;
  if (e <= 0) {
    // A subnormal half: the implicit bit joins the mantissa, shifted further.
    if (e < -10) return sign;
    mantissa |= 0x800000;
    shift = 14 - e;
    base = 0;
  }
  let half = base | (mantissa >>> shift);
  const rest = mantissa & ((1 << shift) - 1);
  const midway = 1 << (shift - 1);
  // A carry out of the mantissa correctly bumps the exponent (up to infinity).
  if (rest > midway || (rest === midway && (half & 1))) half += 1;
  return sign | half;
}

/** A safetensors file with its F32 tensors as F16 (other dtypes kept), names in order. */
function halveSafetensors(bytes) {
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  const headerLength = Number(view.getBigUint64(0, true));
  const header = JSON.parse(new TextDecoder().decode(bytes.subarray(8, 8 + headerLength)));
  const data = bytes.subarray(8 + headerLength);
  const out = {};
  if (header.__metadata__) out.__metadata__ = header.__metadata__;
  const chunks = [];
  let at = 0;
  const names = Object.keys(header).filter((k) => k !== '__metadata__');
  names.sort((a, b) => header[a].data_offsets[0] - header[b].data_offsets[0]);
  for (const name of names) {
    const { dtype, shape, data_offsets: [begin, end] } = header[name];
    let chunk = data.subarray(begin, end);
    let outType = dtype;
    if (dtype === 'F32') {
      const values = new Float32Array(chunk.buffer.slice(chunk.byteOffset, chunk.byteOffset + chunk.byteLength));
      const halves = new Uint16Array(values.length);
      values.forEach((v, i) => { halves[i] = halfBits(v); });
      chunk = new Uint8Array(halves.buffer);
      outType = 'F16';
    }
    out[name] = { dtype: outType, shape, data_offsets: [at, at + chunk.length] };
    chunks.push(chunk);
    at += chunk.length;
  }
  let json = JSON.stringify(out);
  // The header is padded with spaces to a multiple of 8 bytes, as safetensors writes it.
  json += ' '.repeat((8 - (Buffer.byteLength(json) % 8)) % 8);
  const head = Buffer.alloc(8);
  head.writeBigUint64LE(BigInt(Buffer.byteLength(json)));
  return Buffer.concat([head, Buffer.from(json), ...chunks]);
}

const sha256 = (bytes) => createHash('sha256').update(bytes).digest('hex');

// Written beside and renamed into place, so a reader never sees half a file.
function writeAtomic(path, bytes) {
  writeFileSync(`${path}.partial`, bytes);
  renameSync(`${path}.partial`, path);
}

/** Whether a safetensors file holds any F32 tensor. */
function hasF32(bytes) {
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  const headerLength = Number(view.getBigUint64(0, true));
  const header = JSON.parse(new TextDecoder().decode(bytes.subarray(8, 8 + headerLength)));
  return Object.entries(header).some(([k, v]) => k !== '__metadata__' && v.dtype === 'F32');
}

function main() {
  mkdirSync(dst, { recursive: true });
  const converted = {};
  for (const name of ['vae', 'dit']) {
    if (!existsSync(join(src, `${name}.safetensors`))) continue;
    const original = readFileSync(join(src, `${name}.safetensors`));
    const manifest = JSON.parse(readFileSync(join(src, `${name}.manifest.json`), 'utf8'));
    if (manifest.sha256 !== sha256(original)) {
      throw new Error(`${name}.safetensors does not match its manifest's sha256`);
    }
    if (!hasF32(original)) {
      console.log(`[half-weights] ${name}: already f16`);
      if (src !== dst) {
        writeAtomic(join(dst, `${name}.safetensors`), original);
        writeAtomic(join(dst, `${name}.manifest.json`), `${JSON.stringify(manifest, null, 2)}\n`);
      }
      continue;
    }
    const halved = halveSafetensors(original);
    const halvedSha = sha256(halved);
    converted[manifest.sha256] = halvedSha;
    manifest.converted_from_sha256 = manifest.sha256;
    manifest.sha256 = halvedSha;
    manifest.dtype = 'f16';
    if (name === 'dit' && converted[manifest.vae_sha256]) {
      manifest.vae_sha256 = converted[manifest.vae_sha256];
      // The half VAE's latent space is not bit-identical to the original's.
      delete manifest.vae_latent_space_sha256;
    }
    writeAtomic(join(dst, `${name}.safetensors`), halved);
    writeAtomic(join(dst, `${name}.manifest.json`), `${JSON.stringify(manifest, null, 2)}\n`);
    console.log(`[half-weights] ${name}: ${original.length} -> ${halved.length} bytes (${dst})`);
  }
}

if (process.argv[1] && resolve(process.argv[1]) === fileURLToPath(import.meta.url)) main();
