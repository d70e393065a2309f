//! The page (`web/index.html`) in a real browser: the wasm module built for
//! `wasm32-unknown-unknown`, the page served over HTTP, headless Chromium driven through
//! chromedriver (WebDriver) to render frames 0–5 of the swarm, and its canvas compared with the
//! same frames rendered natively by [`lgh_web::Renderer`]: pixel for pixel, and the linear
//! floats bit for bit (the core's float path — libm's, not a platform's — is the same in both).
//!
//! Needs Chromium and its driver (`apt-get install chromium chromium-driver`) and the wasm
//! target (`rustup target add wasm32-unknown-unknown`): without them the test says SKIPPED and
//! passes, unless `LGH_REQUIRE_BROWSER` or `LGH_REQUIRE_WASM` is set (`.ci/run` installs both
//! and sets both), where it fails ([`lgh_tests::Piece`]). `LGH_WEB_BENCH=1` also times 10K and
//! 100K lights at 256² in Chromium (the browser's frame times, to set against the native ones of
//! `web/examples/frames.rs`).
//!
//! The page's WebGPU path (`web/gpu`: lgh-gpu's WGSL kernel in the browser) is tested the same
//! way in Chromium's WebGPU on SwiftShader (`--enable-unsafe-webgpu --enable-unsafe-swiftshader
//! --use-webgpu-adapter=swiftshader`), against the native CPU frames within the query's
//! tolerance; it also needs `wasm-bindgen` (the CLI of Cargo.lock's wasm-bindgen version).

use std::io::{BufRead, BufReader, Read, Write};
use std::net::{TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use lgh_tests::Piece;
use serde_json::{json, Value};

/// The workspace's root.
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap()
        .to_path_buf()
}

/// Whether rustup's `wasm32-unknown-unknown` target is installed: its standard library is in
/// the sysroot.
fn wasm_target_installed() -> bool {
    let rustc = std::env::var("RUSTC").unwrap_or_else(|_| "rustc".into());
    Command::new(rustc)
        .args([
            "--print",
            "target-libdir",
            "--target",
            "wasm32-unknown-unknown",
        ])
        .output()
        .ok()
        .filter(|o| o.status.success())
        .and_then(|o| std::fs::read_dir(String::from_utf8_lossy(&o.stdout).trim()).ok())
        .is_some_and(|mut entries| entries.next().is_some())
}

/// Builds `lgh_web.wasm` (the `wasm` profile: release, stripped) into a target folder of its
/// own and returns its path.
fn build_wasm() -> PathBuf {
    let target = root().join("target/wasm-test");
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let status = Command::new(cargo)
        .current_dir(root())
        .args(["build", "-p", "lgh-web", "--profile", "wasm"])
        .args(["--target", "wasm32-unknown-unknown"])
        .arg("--target-dir")
        .arg(&target)
        .status()
        .expect("cargo");
    assert!(
        status.success(),
        "building lgh_web.wasm failed (rustup target add wasm32-unknown-unknown)"
    );
    target.join("wasm32-unknown-unknown/wasm/lgh_web.wasm")
}

/// Builds `lgh_web_gpu.wasm` and binds it for the page (`wasm-bindgen --target web`) into a
/// folder it returns, or `None` (after [`Piece::missing`]) without the `wasm-bindgen` CLI.
fn build_gpu_package() -> Option<PathBuf> {
    if !lgh_tests::runs("wasm-bindgen", &["--version"]) {
        Piece::WasmTarget.missing(
            "no wasm-bindgen CLI (cargo install wasm-bindgen-cli --version <Cargo.lock's wasm-bindgen>)",
        );
        return None;
    }
    let target = root().join("target/wasm-test");
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let status = Command::new(cargo)
        .current_dir(root())
        .args(["build", "-p", "lgh-web-gpu", "--profile", "wasm"])
        .args(["--target", "wasm32-unknown-unknown"])
        .arg("--target-dir")
        .arg(&target)
        .status()
        .expect("cargo");
    assert!(status.success(), "building lgh_web_gpu.wasm failed");
    let package = target.join("gpu-pkg");
    let status = Command::new("wasm-bindgen")
        .args(["--target", "web", "--no-typescript", "--out-dir"])
        .arg(&package)
        .arg(target.join("wasm32-unknown-unknown/wasm/lgh_web_gpu.wasm"))
        .status()
        .expect("wasm-bindgen");
    assert!(status.success(), "wasm-bindgen failed");
    Some(package)
}

/// Serves `web/` (and `wasm` as `lgh_web.wasm`) on a free port until the test ends; returns
/// the port.
fn serve(wasm: PathBuf) -> u16 {
    serve_with(wasm, None)
}

/// [`serve`], with the WebGPU path's package as `gpu/pkg/` where there is one.
fn serve_with(wasm: PathBuf, package: Option<PathBuf>) -> u16 {
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let port = listener.local_addr().unwrap().port();
    let web = root().join("web");
    std::thread::spawn(move || {
        for stream in listener.incoming().flatten() {
            let (web, wasm, package) = (web.clone(), wasm.clone(), package.clone());
            std::thread::spawn(move || answer(stream, &web, &wasm, package.as_deref()));
        }
    });
    port
}

/// One HTTP request for a static file.
fn answer(mut stream: TcpStream, web: &Path, wasm: &Path, package: Option<&Path>) {
    let mut line = String::new();
    let mut reader = BufReader::new(stream.try_clone().unwrap());
    if reader.read_line(&mut line).is_err() {
        return;
    }
    loop {
        let mut header = String::new();
        if reader.read_line(&mut header).unwrap_or(0) <= 2 {
            break;
        }
    }
    let path = line.split_whitespace().nth(1).unwrap_or("/");
    let path = path.split('?').next().unwrap().trim_start_matches('/');
    let (file, kind) = match path {
        "" | "index.html" => (web.join("index.html"), "text/html"),
        "main.js" => (web.join("main.js"), "text/javascript"),
        "lgh_web.wasm" => (wasm.to_path_buf(), "application/wasm"),
        "gpu/pkg/lgh_web_gpu.js" => match package {
            Some(p) => (p.join("lgh_web_gpu.js"), "text/javascript"),
            None => (PathBuf::new(), ""),
        },
        "gpu/pkg/lgh_web_gpu_bg.wasm" => match package {
            Some(p) => (p.join("lgh_web_gpu_bg.wasm"), "application/wasm"),
            None => (PathBuf::new(), ""),
        },
        _ => (PathBuf::new(), ""),
    };
    let reply = match std::fs::read(&file) {
        Ok(body) => {
            let head = format!(
                "HTTP/1.1 200 OK\r\nContent-Type: {kind}\r\nContent-Length: {}\r\nConnection: close\r\n\r\n",
                body.len()
            );
            [head.into_bytes(), body].concat()
        }
        Err(_) => {
            b"HTTP/1.1 404 Not Found\r\nContent-Length: 0\r\nConnection: close\r\n\r\n".to_vec()
        }
    };
    let _ = stream.write_all(&reply);
}

/// A WebDriver command: `method` on `path` of the driver at `port`, with a JSON body; the
/// reply's `value`.
fn webdriver(port: u16, method: &str, path: &str, body: Option<&Value>) -> Value {
    let mut stream = TcpStream::connect(("127.0.0.1", port)).unwrap();
    stream
        .set_read_timeout(Some(Duration::from_secs(120)))
        .unwrap();
    let body = body.map(Value::to_string).unwrap_or_default();
    let request = format!(
        "{method} {path} HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nContent-Type: application/json\r\nContent-Length: {}\r\nConnection: close\r\n\r\n{body}",
        body.len()
    );
    stream.write_all(request.as_bytes()).unwrap();
    // The head, then as many bytes as it says (the driver may keep the connection open).
    let mut reply = Vec::new();
    let mut buffer = [0u8; 65536];
    let split = loop {
        if let Some(at) = reply.windows(4).position(|w| w == b"\r\n\r\n") {
            break at;
        }
        let n = stream.read(&mut buffer).unwrap();
        assert!(n > 0, "{method} {path}: the driver closed the connection");
        reply.extend_from_slice(&buffer[..n]);
    };
    let head = String::from_utf8_lossy(&reply[..split]).to_lowercase();
    let mut body = reply[split + 4..].to_vec();
    let length = head
        .lines()
        .find_map(|l| l.strip_prefix("content-length:"))
        .map(|v| v.trim().parse::<usize>().unwrap());
    let chunked = head.contains("transfer-encoding: chunked");
    loop {
        let done = match length {
            Some(n) => body.len() >= n,
            None if chunked => body.windows(5).any(|w| w == b"0\r\n\r\n"),
            None => false,
        };
        if done {
            break;
        }
        let n = stream.read(&mut buffer).unwrap();
        if n == 0 {
            break;
        }
        body.extend_from_slice(&buffer[..n]);
    }
    if chunked {
        body = unchunk(&body);
    }
    let value: Value = serde_json::from_slice(&body)
        .unwrap_or_else(|e| panic!("{method} {path}: {e}: {}", String::from_utf8_lossy(&body)));
    value["value"].clone()
}

/// An HTTP body sent in chunks, joined.
fn unchunk(mut body: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    loop {
        let line = body.windows(2).position(|w| w == b"\r\n").unwrap();
        let size =
            usize::from_str_radix(String::from_utf8_lossy(&body[..line]).trim(), 16).unwrap();
        if size == 0 {
            return out;
        }
        out.extend_from_slice(&body[line + 2..line + 2 + size]);
        body = &body[line + 2 + size + 2..];
    }
}

/// Standard base64 decoded (the `base64` crate, as lgh-cli's manifests use it).
fn base64(text: &str) -> Vec<u8> {
    use base64::Engine as _;
    base64::engine::general_purpose::STANDARD
        .decode(text)
        .expect("the page's base64")
}

/// chromedriver on a free port, killed when dropped.
struct Driver {
    child: Child,
    port: u16,
    session: String,
}

impl Driver {
    /// chromedriver started and a headless Chromium session opened, or `None` (after
    /// [`Piece::missing`]) where they are not installed.
    fn start() -> Option<Self> {
        Self::start_with(&["--disable-gpu"])
    }

    /// [`start`](Self::start), Chromium given `args` besides the headless ones.
    fn start_with(args: &[&str]) -> Option<Self> {
        let driver = [
            "chromedriver",
            "/usr/bin/chromedriver",
            "/usr/lib/chromium/chromedriver",
        ]
        .into_iter()
        .find(|d| lgh_tests::runs(d, &["--version"]));
        let chromium = [
            "/usr/bin/chromium",
            "/usr/bin/chromium-browser",
            "/usr/bin/google-chrome",
        ]
        .into_iter()
        .find(|b| Path::new(b).exists());
        let (Some(driver), Some(chromium)) = (driver, chromium) else {
            let what = match (driver, chromium) {
                (None, None) => "no Chromium and no chromedriver",
                (None, _) => "no chromedriver",
                _ => "no Chromium",
            };
            Piece::Browser.missing(what);
            return None;
        };
        let port = TcpListener::bind("127.0.0.1:0")
            .unwrap()
            .local_addr()
            .unwrap()
            .port();
        let child = Command::new(driver)
            .arg(format!("--port={port}"))
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        let mut driver = Driver {
            child,
            port,
            session: String::new(),
        };
        let t = Instant::now();
        while TcpStream::connect(("127.0.0.1", port)).is_err() {
            assert!(
                t.elapsed() < Duration::from_secs(30),
                "chromedriver did not start"
            );
            std::thread::sleep(Duration::from_millis(100));
        }
        let chromium_args = [
            &["--headless=new", "--no-sandbox", "--disable-dev-shm-usage"][..],
            args,
        ]
        .concat();
        let capabilities = json!({ "capabilities": { "alwaysMatch": {
            "browserName": "chrome",
            "goog:chromeOptions": {
                "binary": chromium,
                "args": chromium_args
            }
        }}});
        let session = webdriver(port, "POST", "/session", Some(&capabilities));
        driver.session = session["sessionId"]
            .as_str()
            .unwrap_or_else(|| panic!("no session: {session}"))
            .to_string();
        Some(driver)
    }

    /// Opens `url` and waits for the page's `window.lghResult`.
    fn result(&self, url: &str) -> Value {
        let s = &self.session;
        webdriver(
            self.port,
            "POST",
            &format!("/session/{s}/url"),
            Some(&json!({ "url": url })),
        );
        let script = json!({ "script": "return window.lghResult || null;", "args": [] });
        let t = Instant::now();
        loop {
            let got = webdriver(
                self.port,
                "POST",
                &format!("/session/{s}/execute/sync"),
                Some(&script),
            );
            if !got.is_null() {
                assert!(got["error"].is_null(), "the page: {}", got["error"]);
                return got;
            }
            assert!(
                t.elapsed() < Duration::from_secs(300),
                "the page gave no result"
            );
            std::thread::sleep(Duration::from_millis(200));
        }
    }
}

impl Drop for Driver {
    fn drop(&mut self) {
        if !self.session.is_empty() {
            let path = format!("/session/{}", self.session);
            let _ = std::panic::catch_unwind(|| webdriver(self.port, "DELETE", &path, None));
        }
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Frames 0..`frames` of `count` lights at `size`², natively: the last one's renderer.
fn native(count: usize, frames: i32, size: usize) -> lgh_web::Renderer {
    let mut r = lgh_web::Renderer::new();
    for frame in 0..frames {
        r.frame(count, frame, size, 2.0).unwrap();
    }
    r
}

#[test]
fn chromium_renders_the_native_frame_pixel_for_pixel() {
    if !wasm_target_installed() {
        return Piece::WasmTarget.missing("no wasm32-unknown-unknown target");
    }
    let Some(driver) = Driver::start() else {
        return;
    };
    let wasm = build_wasm();
    let port = serve(wasm.clone());
    // Frames 0–5: built, updated three times, rebuilt at 4, updated at 5.
    let (count, frames, size) = (20_000usize, 6, 64);
    let url = format!(
        "http://127.0.0.1:{port}/index.html?test={frames}&lights={count}&size={size}&alpha=2&backend=cpu"
    );
    let got = driver.result(&url);
    eprintln!("{}: frames in {} ms", got["user_agent"], got["ms"]);
    assert_eq!(got["backend"], "cpu");
    let want = native(count, frames, size);
    assert_eq!(got["size"], size);
    let canvas = base64(got["canvas"].as_str().unwrap());
    assert_eq!(canvas.len(), want.rgba().len());
    let differ = canvas
        .iter()
        .zip(want.rgba())
        .filter(|(a, b)| a != b)
        .count();
    assert_eq!(
        differ,
        0,
        "{differ} of {} canvas bytes differ",
        canvas.len()
    );
    let floats: Vec<f32> = base64(got["rgb"].as_str().unwrap())
        .chunks(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect();
    assert_eq!(floats.len(), want.rgb().len());
    let differ = floats
        .iter()
        .zip(want.rgb())
        .filter(|(a, b)| a.to_bits() != b.to_bits())
        .count();
    assert_eq!(differ, 0, "{differ} of {} floats differ", floats.len());
    assert!(want.rgb().iter().any(|&v| v > 0.0), "a lit frame");
    let bytes = std::fs::metadata(&wasm).unwrap().len();
    eprintln!("lgh_web.wasm: {bytes} bytes");

    if std::env::var("LGH_WEB_BENCH").is_ok_and(|v| v == "1") {
        for count in [10_000usize, 100_000] {
            let url = format!(
                "http://127.0.0.1:{port}/index.html?test=8&lights={count}&size=256&alpha=2"
            );
            let got = driver.result(&url);
            println!(
                "chromium, {count} lights, 256²: frames 0-7 in {} ms",
                got["ms"]
            );
        }
    }
}

/// The page's WebGPU path in Chromium's WebGPU on SwiftShader: the same frames as the native CPU
/// path within the query's tolerance — both sum the same non-negative terms, at most `count`
/// a pixel, in different orders: `(2N + 32)·u` of the pixel (lgh-gpu's `tests/shade.rs`).
#[test]
fn chromium_renders_the_native_frame_on_webgpu_within_the_tolerance() {
    if !wasm_target_installed() {
        return Piece::WasmTarget.missing("no wasm32-unknown-unknown target");
    }
    let Some(package) = build_gpu_package() else {
        return;
    };
    let webgpu = [
        "--enable-unsafe-webgpu",
        "--enable-unsafe-swiftshader",
        "--use-webgpu-adapter=swiftshader",
    ];
    let Some(driver) = Driver::start_with(&webgpu) else {
        return;
    };
    let port = serve_with(build_wasm(), Some(package));
    let (count, frames, size) = (2000usize, 6, 48);
    let url = format!(
        "http://127.0.0.1:{port}/index.html?test={frames}&lights={count}&size={size}&alpha=2&backend=webgpu"
    );
    let got = driver.result(&url);
    eprintln!("WebGPU on {}: frames in {} ms", got["adapter"], got["ms"]);
    assert_eq!(got["backend"], "webgpu");
    let want = native(count, frames, size);
    let floats: Vec<f32> = base64(got["rgb"].as_str().unwrap())
        .chunks(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect();
    assert_eq!(floats.len(), want.rgb().len());
    let bound = (2 * count + 32) as f32 / (1u32 << 24) as f32;
    let mut worst = 0.0f32;
    for (g, c) in floats.iter().zip(want.rgb()) {
        let diff = (g - c).abs();
        assert!(diff <= bound * c.abs(), "WebGPU {g} against the native {c}");
        if *c > 0.0 {
            worst = worst.max(diff / (bound * c));
        }
    }
    assert!(want.rgb().iter().any(|&v| v > 0.0), "a lit frame");
    eprintln!("WebGPU against native: largest difference {worst:.3} of the bound");
}
