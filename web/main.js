// The page: loads lgh_web.wasm (built by `cargo build -p lgh-web --profile wasm --target
// wasm32-unknown-unknown`, copied beside this file) and renders its frames into the canvas. Where
// the browser has WebGPU, the pixels are lit on the GPU by lgh-gpu's WGSL kernel through
// gpu/pkg/lgh_web_gpu.js (web/gpu: `cargo build -p lgh-web-gpu --profile wasm --target
// wasm32-unknown-unknown`, then `wasm-bindgen --target web --out-dir web/gpu/pkg` on its .wasm);
// otherwise, or where that fails, in wasm on the CPU. The page says which.
//
// Query parameters: lights, alpha, size set the sliders' starting values; backend=webgpu or
// backend=cpu insists on one (webgpu fails where the browser has none); `test=N` renders frames
// 0..N-1 once, as fast as it can, and leaves the last frame's canvas pixels, its linear floats,
// each frame's milliseconds and the backend in `window.lghResult` (web/tests/browser.rs reads
// them).

const LIGHTS = [1000, 10000, 50000, 100000, 200000, 500000];
const SIZES = [64, 128, 256, 512];

const params = new URLSearchParams(location.search);
const canvas = document.getElementById("canvas");
const context = canvas.getContext("2d");
const stats = document.getElementById("stats");
const slider = (id, values, show) => {
  const input = document.getElementById(id);
  const value = () => (values ? values[+input.value] : +input.value);
  const label = document.getElementById(id + "-value");
  const update = () => (label.textContent = show(value()));
  input.addEventListener("input", update);
  update();
  return { input, value };
};
const lights = slider("lights", LIGHTS, (v) => v.toLocaleString("en"));
const alpha = slider("alpha", null, (v) => v.toFixed(1));
const size = slider("size", SIZES, (v) => `${v}`);
const start = (s, values, key) => {
  if (!params.has(key)) return;
  const want = +params.get(key);
  if (values) {
    const at = values.indexOf(want);
    if (at >= 0) s.input.value = at;
  } else {
    s.input.value = want;
  }
  s.input.dispatchEvent(new Event("input"));
};
start(lights, LIGHTS, "lights");
start(alpha, null, "alpha");
start(size, SIZES, "size");

function fail(message) {
  document.getElementById("error").textContent = message;
  window.lghResult = { error: message };
}

const bytes = await (await fetch("lgh_web.wasm")).arrayBuffer();
const { instance } = await WebAssembly.instantiate(bytes, {});
const wasm = instance.exports;

// WebGPU where the browser has it (and backend=cpu does not say otherwise).
const wanted = params.get("backend") ?? "auto";
let gpu = null;
let adapter = "";
let whyNot = "backend=cpu";
if (wanted !== "cpu") {
  try {
    if (!navigator.gpu) throw new Error("this browser has no WebGPU");
    gpu = await import("./gpu/pkg/lgh_web_gpu.js");
    await gpu.default();
    adapter = await gpu.lgh_gpu_start();
  } catch (e) {
    gpu = null;
    whyNot = String(e.message ?? e);
  }
}
const backend = gpu ? "webgpu" : "cpu";
document.getElementById("backend").textContent = gpu
  ? `lit on the GPU through WebGPU (${adapter || "adapter"}), lgh-gpu's WGSL`
  : `lit in wasm on the CPU (no WebGPU: ${whyNot})`;

// Frame `frame` of `count` lights at `side`² pixels: into the canvas, and its milliseconds.
async function render(count, frame, side, a) {
  const t0 = performance.now();
  let rgba;
  if (gpu) {
    await gpu.lgh_gpu_frame(count, frame, side, a);
    rgba = gpu.lgh_gpu_rgba();
  } else {
    const status = wasm.lgh_web_frame(count, frame, side, a);
    if (status !== 0) {
      const text = new Uint8Array(wasm.memory.buffer, wasm.lgh_web_error(), wasm.lgh_web_error_len());
      throw new Error(new TextDecoder().decode(text));
    }
    rgba = new Uint8ClampedArray(wasm.memory.buffer, wasm.lgh_web_rgba(), 4 * side * side);
  }
  const ms = performance.now() - t0;
  if (canvas.width !== side) canvas.width = canvas.height = side;
  context.putImageData(new ImageData(new Uint8ClampedArray(rgba), side, side), 0, 0);
  return ms;
}

// The last frame's linear floats.
const linear = (side) =>
  gpu
    ? new Float32Array(gpu.lgh_gpu_rgb())
    : new Float32Array(new Float32Array(wasm.memory.buffer, wasm.lgh_web_rgb(), 3 * side * side));

const base64 = (view) => {
  const u8 = new Uint8Array(view.buffer, view.byteOffset, view.byteLength);
  let s = "";
  for (let i = 0; i < u8.length; i += 0x8000) s += String.fromCharCode(...u8.subarray(i, i + 0x8000));
  return btoa(s);
};

if (params.has("test")) {
  // Frames 0..N-1 back to back, then what the test compares.
  try {
    if (wanted === "webgpu" && !gpu) throw new Error(`WebGPU: ${whyNot}`);
    // Any light count and size (the sliders offer a few).
    const n = +params.get("test");
    const count = +(params.get("lights") ?? lights.value());
    const side = +(params.get("size") ?? size.value());
    const a = +(params.get("alpha") ?? alpha.value());
    const ms = [];
    for (let frame = 0; frame < n; frame++) ms.push(await render(count, frame, side, a));
    const pixels = context.getImageData(0, 0, side, side).data;
    window.lghResult = {
      backend,
      adapter,
      size: side,
      ms,
      canvas: base64(pixels),
      rgb: base64(linear(side)),
      wasm_bytes: bytes.byteLength,
      user_agent: navigator.userAgent,
    };
  } catch (e) {
    fail(String(e));
  }
} else {
  let frame = 0;
  let smoothed = 0;
  const step = async () => {
    try {
      const count = lights.value();
      const ms = await render(count, frame, size.value(), alpha.value());
      smoothed = smoothed ? 0.9 * smoothed + 0.1 * ms : ms;
      // The CPU path counts the lights it sums; the GPU's does not read them back.
      const perPixel = gpu
        ? ""
        : `${(wasm.lgh_web_lights_shaded() / (size.value() * size.value())).toFixed(1)} lights a pixel  `;
      stats.textContent =
        `frame ${String(frame).padStart(2)}  ${ms.toFixed(1).padStart(6)} ms ` +
        `(mean ${smoothed.toFixed(1)} ms)  ${perPixel}` +
        `${(bytes.byteLength / 1024).toFixed(0)} KiB of wasm`;
      frame = (frame + 1) % 48;
      requestAnimationFrame(step);
    } catch (e) {
      fail(String(e));
    }
  };
  requestAnimationFrame(step);
}
