//! The farm recipe on a real scheduler (issue 15): a single-node Slurm cluster started and
//! stopped by the test (`farm/slurm-local.sh`, Debian's slurm-wlm and munge), the dev fire
//! rendered by a job array of `farm/lgh-array.sbatch` tasks, every frame's pixels the same bits
//! as one process's.
//!
//! Without Slurm, or not as root (slurmd runs jobs as their user), the test says SKIPPED; with
//! `LGH_REQUIRE_SLURM` set (CI, which installs Slurm) it fails instead, so a missing install
//! cannot pass as green ([`lgh_tests::Piece`]). The scheduler is checked before the data, so the
//! requirement holds whatever data is here.

mod common;

use common::{exr_bits, lgh_ok};
use lgh_tests::fire_frame;
use std::path::{Path, PathBuf};
use std::process::Command;

/// Skips the test, or fails it when Slurm is required.
fn unavailable(why: &str) {
    lgh_tests::Piece::Slurm.missing(why);
}

fn farm_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../farm")
}

/// Stops the cluster when the test ends, passed or not.
struct Cluster(PathBuf);

impl Drop for Cluster {
    fn drop(&mut self) {
        let _ = Command::new(farm_dir().join("slurm-local.sh"))
            .arg("stop")
            .arg(&self.0)
            .status();
    }
}

#[test]
fn a_slurm_job_array_renders_the_same_frames_as_one_process() {
    let has = |tool: &str| {
        ["/usr/sbin", "/usr/bin", "/sbin", "/bin"]
            .iter()
            .any(|d| Path::new(d).join(tool).is_file())
    };
    if let Some(missing) = ["sbatch", "slurmctld", "slurmd", "munged"]
        .into_iter()
        .find(|t| !has(t))
    {
        return unavailable(&format!("{missing} is not installed"));
    }
    let id = Command::new("id").arg("-u").output().unwrap();
    if String::from_utf8_lossy(&id.stdout).trim() != "0" {
        return unavailable("the test is not root, which a local slurmd needs");
    }
    let Some(f56) = fire_frame(56) else { return };

    let dir = tempfile::tempdir().unwrap();
    let cluster_dir = dir.path().join("cluster");
    let start = Command::new(farm_dir().join("slurm-local.sh"))
        .arg("start")
        .arg(&cluster_dir)
        .output()
        .unwrap();
    let _cluster = Cluster(cluster_dir.clone());
    assert!(
        start.status.success(),
        "the local Slurm cluster did not start: {}",
        String::from_utf8_lossy(&start.stderr)
    );
    let conf = cluster_dir.join("slurm.conf");

    let (farm, single) = (dir.path().join("farm"), dir.path().join("single"));
    std::fs::create_dir_all(&farm).unwrap();
    std::fs::create_dir_all(&single).unwrap();
    let manifest = dir.path().join("fire.json");
    let settings = [
        "--vdb",
        f56.to_str().unwrap(),
        "--frames",
        "50..56",
        "--width",
        "24",
        "--height",
        "14",
        "--shadows",
        "none",
        "--quiet",
    ];
    let with = |extra: &[&str]| {
        let mut a = vec!["explosion"];
        a.extend(settings);
        a.extend(extra);
        lgh_ok(&a);
    };
    let farm_out = farm.join("fire.exr");
    with(&[
        "--out",
        farm_out.to_str().unwrap(),
        "--prepare",
        manifest.to_str().unwrap(),
    ]);
    // 7 frames, 2 a task: tasks 0..3, the last with one frame.
    let o = Command::new("sbatch")
        .args(["--wait", "--array=0-3", "--cpus-per-task=1"])
        .arg(format!("--output={}/lgh-%A_%a.log", dir.path().display()))
        .arg(format!("--chdir={}", dir.path().display()))
        .arg(farm_dir().join("lgh-array.sbatch"))
        .arg(&manifest)
        .args(["50", "56", "2"])
        .env("SLURM_CONF", &conf)
        .env("LGH", env!("CARGO_BIN_EXE_lgh"))
        .output()
        .unwrap();
    let logs: String = std::fs::read_dir(dir.path())
        .unwrap()
        .filter_map(|e| {
            let p = e.ok()?.path();
            let log = p.extension()? == "log";
            log.then(|| std::fs::read_to_string(&p).unwrap_or_default())
        })
        .collect();
    assert!(
        o.status.success(),
        "the job array failed: {}{}\ntask logs:\n{logs}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    assert_eq!(logs.matches("lgh explosion:").count(), 4, "{logs}");

    with(&["--out", single.join("fire.exr").to_str().unwrap()]);
    for f in 50..=56 {
        let name = format!("fire_{f:04}.exr");
        assert_eq!(
            exr_bits(&farm.join(&name)),
            exr_bits(&single.join(&name)),
            "frame {f}: the job array's pixels differ from one process's"
        );
    }
}
