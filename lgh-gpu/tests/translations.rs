//! For engines not on wgpu (Unreal, Godot, Unity, an in-house RHI): each WGSL entry point translated
//! by naga — wgpu's own shader compiler — to SPIR-V, HLSL (shader model 6.0), GLSL (4.30
//! compute) and MSL (2.4), committed in `lgh-gpu/generated/` beside a buffer layout that is a
//! contract (`lgh_gpu::layout`), one file a kernel and language (`ENTRY.spv`, …). This test translates them again and fails if a committed file
//! is missing or differs: `LGH_BLESS=1 cargo test -p lgh-gpu --test translations` rewrites them.

use std::path::{Path, PathBuf};

use naga::{back, front, valid};

/// Each translation of `wgsl`'s `entry`: (file extension, contents).
fn translate(wgsl: &str, entry: &str) -> Vec<(&'static str, Vec<u8>)> {
    let module =
        front::wgsl::parse_str(wgsl).unwrap_or_else(|e| panic!("{}", e.emit_to_string(wgsl)));
    let mut validator =
        valid::Validator::new(valid::ValidationFlags::all(), valid::Capabilities::all());
    let info = validator
        .validate(&module)
        .unwrap_or_else(|e| panic!("{}", e.emit_to_string(wgsl)));
    let stage = naga::ShaderStage::Compute;

    let spv_pipeline = back::spv::PipelineOptions {
        shader_stage: stage,
        entry_point: entry.into(),
    };
    // The flags spelled out: naga's default adds `DEBUG` (the names, `OpName`) in a debug
    // build only, so the same WGSL gave other SPIR-V under `--release`. The committed files
    // keep the names, which an engine's tools show.
    let spv_options = back::spv::Options {
        lang_version: (1, 3),
        flags: back::spv::WriterFlags::ADJUST_COORDINATE_SPACE
            | back::spv::WriterFlags::LABEL_VARYINGS
            | back::spv::WriterFlags::CLAMP_FRAG_DEPTH
            | back::spv::WriterFlags::DEBUG,
        ..Default::default()
    };
    let spv = back::spv::write_vec(&module, &info, &spv_options, Some(&spv_pipeline)).unwrap();
    let spv: Vec<u8> = spv.iter().flat_map(|w| w.to_le_bytes()).collect();

    let mut hlsl = String::new();
    let hlsl_options = back::hlsl::Options {
        shader_model: back::hlsl::ShaderModel::V6_0,
        ..Default::default()
    };
    let hlsl_pipeline = back::hlsl::PipelineOptions {
        entry_point: Some((stage, entry.into())),
    };
    back::hlsl::Writer::new(&mut hlsl, &hlsl_options, &hlsl_pipeline)
        .write(&module, &info, None)
        .unwrap();

    let msl_options = back::msl::Options {
        lang_version: (2, 4),
        ..Default::default()
    };
    let msl_pipeline = back::msl::PipelineOptions {
        entry_point: Some((stage, entry.into())),
        ..Default::default()
    };
    let (msl, _) = back::msl::write_string(&module, &info, &msl_options, &msl_pipeline).unwrap();

    let mut glsl = String::new();
    let glsl_options = back::glsl::Options {
        version: back::glsl::Version::Desktop(430),
        ..Default::default()
    };
    let glsl_pipeline = back::glsl::PipelineOptions {
        shader_stage: stage,
        entry_point: entry.into(),
        multiview: None,
    };
    back::glsl::Writer::new(
        &mut glsl,
        &module,
        &info,
        &glsl_options,
        &glsl_pipeline,
        naga::proc::BoundsCheckPolicies::default(),
    )
    .unwrap()
    .write()
    .unwrap();

    vec![
        ("spv", spv),
        ("hlsl", hlsl.into_bytes()),
        ("comp.glsl", glsl.into_bytes()),
        ("metal", msl.into_bytes()),
    ]
}

fn crate_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).to_path_buf()
}

#[test]
fn the_committed_translations_are_current() {
    let bless = std::env::var_os("LGH_BLESS").is_some_and(|v| !v.is_empty());
    let mut stale = Vec::new();
    for kernel in lgh_gpu::kernels::ALL {
        for entry in kernel.entries {
            check(kernel.source(), entry, bless, &mut stale);
        }
    }
    assert!(
        stale.is_empty(),
        "missing or stale: {}\n(`LGH_BLESS=1 cargo test -p lgh-gpu --test translations` rewrites them)",
        stale.join(", ")
    );
}

/// `entry`'s translations against the committed `generated/ENTRY.EXT` (rewritten if `bless`).
fn check(wgsl: &str, entry: &str, bless: bool, stale: &mut Vec<String>) {
    for (ext, contents) in translate(wgsl, entry) {
        let path = crate_dir().join("generated").join(format!("{entry}.{ext}"));
        if std::fs::read(&path).ok().as_deref() == Some(&contents[..]) {
            continue;
        }
        if bless {
            std::fs::create_dir_all(path.parent().unwrap()).unwrap();
            std::fs::write(&path, &contents).unwrap();
        } else {
            stale.push(path.display().to_string());
        }
    }
}

/// The translations are a function of the WGSL alone: the same bytes twice.
#[test]
fn translating_twice_gives_the_same_bytes() {
    let wgsl = lgh_gpu::kernels::BUILD.source();
    assert_eq!(
        translate(wgsl, "moment_parts"),
        translate(wgsl, "moment_parts")
    );
}

/// The committed SPIR-V and GLSL pass Khronos' own validators — `spirv-val` for Vulkan 1.1 and
/// `glslangValidator` for GLSL 4.30 compute — beyond naga's validation of the WGSL. Without
/// them (`apt-get install spirv-tools glslang-tools`) SKIPPED, unless required
/// (`lgh_tests::Piece::ShaderTools`).
#[test]
fn the_translations_pass_khronos_validators() {
    use std::process::Command;
    let tools = ["spirv-val", "glslangValidator"];
    if let Some(missing) = tools.iter().find(|t| !lgh_tests::runs(t, &["--version"])) {
        return lgh_tests::Piece::ShaderTools.missing(&format!("no {missing}"));
    }
    let generated = crate_dir().join("generated");
    let valid = |file: &Path| -> Result<(), String> {
        let name = file.file_name().unwrap().to_string_lossy().to_string();
        let out = if name.ends_with(".spv") {
            Command::new("spirv-val")
                .args(["--target-env", "vulkan1.1"])
                .arg(file)
                .output()
        } else {
            Command::new("glslangValidator")
                .args(["-S", "comp"])
                .arg(file)
                .output()
        }
        .unwrap();
        if out.status.success() {
            Ok(())
        } else {
            Err(format!(
                "{name}: {}{}",
                String::from_utf8_lossy(&out.stdout),
                String::from_utf8_lossy(&out.stderr)
            ))
        }
    };
    let mut checked = 0;
    for kernel in lgh_gpu::kernels::ALL {
        for entry in kernel.entries {
            for ext in ["spv", "comp.glsl"] {
                valid(&generated.join(format!("{entry}.{ext}"))).unwrap();
                checked += 1;
            }
        }
    }
    assert_eq!(
        checked,
        2 * lgh_gpu::kernels::ALL
            .iter()
            .map(|k| k.entries.len())
            .sum::<usize>()
    );
    // The validators do refuse: a SPIR-V module cut short, a GLSL kernel with a type error.
    let dir = std::env::temp_dir().join(format!("lgh-gpu-validators-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let spv = std::fs::read(generated.join("shade.spv")).unwrap();
    std::fs::write(dir.join("cut.spv"), &spv[..spv.len() / 2]).unwrap();
    std::fs::write(
        dir.join("bad.comp.glsl"),
        "#version 430 core\nlayout(local_size_x = 1) in;\nvoid main() { float x = vec3(1.0); }\n",
    )
    .unwrap();
    assert!(valid(&dir.join("cut.spv")).is_err());
    assert!(valid(&dir.join("bad.comp.glsl")).is_err());
    let _ = std::fs::remove_dir_all(&dir);
}
