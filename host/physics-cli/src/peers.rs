//! `vphys peers …`: the shared peer models, Pinocchio fixtures and the ABA timing comparison.

use anyhow::{bail, Context, Result};
use clap::Subcommand;
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::process::Command;
use virtual_physics::dynamics::{aba, Workspace};
use virtual_physics::measure::table3::time_ns;
use virtual_physics::model::builders::{chain, humanoid, peer_models, random_state};
use virtual_physics::model::description::ModelDescription;

const INSTALL: &str =
    "Pinocchio is not installed for this Python: install it with `pip install pin` \
     (or point --python at an interpreter that has it)";

#[derive(Subcommand)]
pub enum PeersCmd {
    /// Writes the peer models' JSON descriptions (the single definition both sides read).
    Models {
        /// Output directory.
        #[arg(long)]
        out: PathBuf,
    },
    /// Regenerates the Pinocchio reference fixtures (tests/fixtures/*.json).
    Fixtures {
        /// Output directory (default: the crate's tests/fixtures).
        #[arg(long)]
        out: Option<PathBuf>,
        #[command(flatten)]
        py: Python,
    },
    /// Steps the same scenes in our engine and in rapier3d (feature `rapier-peer`), sleeping
    /// off and on: ms per step, ratio, drift. With --suite, the committed benchmark suite
    /// (resting stacks and scenes in motion) at both engines' defaults, sleeping off.
    Rapier {
        /// One JSON object `{"rows": [...]}` instead of a table.
        #[arg(long)]
        json: bool,
        #[command(flatten)]
        stacks: Stacks,
        /// Run the committed suite (`host/physics/scenes/suite/` and the two stacks) instead
        /// of --scenes: ms per step, ratio, ns per contact point per substep, deepest overlap.
        #[arg(long, conflicts_with = "scenes")]
        suite: bool,
        /// With --suite: runs of each scene, ours and rapier interleaved; each keeps its best
        /// median (1 … 20).
        #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u16).range(1..=20))]
        repeats: u16,
    },
    /// Accuracy against time on the stacking scenes: ours over its substeps, rapier3d over
    /// its solver iterations (feature `rapier-peer`), sleeping off; the points, the front at
    /// equal drift, and optionally the chart.
    Front {
        /// One JSON object `{"points": [...], "front": [...]}` instead of tables.
        #[arg(long)]
        json: bool,
        #[command(flatten)]
        stacks: Stacks,
        /// Draw the chart here (`.svg` and `.png`).
        #[arg(long)]
        chart: Option<PathBuf>,
    },
    /// The accuracy report's tumbling box in ours, MuJoCo (when installed) and rapier3d
    /// (feature `rapier-peer`): error against CPU time per simulated second.
    Tumbling {
        /// One JSON object `{"points": [...], "missing": [...]}` instead of a table.
        #[arg(long)]
        json: bool,
        /// Python interpreter with the `mujoco` package.
        #[arg(long, default_value = "python3")]
        python: String,
        /// The MuJoCo script.
        #[arg(long, default_value = crate::tumbling_peers::MUJOCO_SCRIPT)]
        script: PathBuf,
        /// Draw the chart here (`.svg` and `.png`).
        #[arg(long)]
        chart: Option<PathBuf>,
    },
    /// An articulated tree in contact (a chain falling onto boxes) in our engine and in
    /// rapier3d's multibodies (feature `rapier-peer`): ms per step and the deepest ground
    /// penetration.
    Multibody {
        /// One JSON object instead of a table.
        #[arg(long)]
        json: bool,
        /// Steps (default: the scene's, 600).
        #[arg(long)]
        steps: Option<u64>,
        /// Scene file (a tree of revolute joints on a free root, with link shapes).
        #[arg(long, default_value = concat!(env!("CARGO_MANIFEST_DIR"), "/../physics/scenes/chain-on-boxes.json"))]
        scene: String,
    },
    /// Box–box manifold cost: ours against parry3d's (feature `rapier-peer`).
    Parry {
        /// One JSON object instead of a table.
        #[arg(long)]
        json: bool,
    },
    /// Times our forward dynamics against Pinocchio's `aba` on the same models.
    Aba {
        /// One JSON object instead of a table.
        #[arg(long)]
        json: bool,
        #[command(flatten)]
        py: Python,
    },
}

/// The stacking scenes a comparison runs, and for how long.
#[derive(clap::Args)]
pub struct Stacks {
    /// Steps (default: each scene's, 600).
    #[arg(long)]
    steps: Option<u64>,
    /// Scenes (built-in names or files).
    #[arg(long, num_args = 1.., default_values_t = crate::front::SCENES.map(String::from))]
    scenes: Vec<String>,
}

#[derive(clap::Args)]
pub struct Python {
    /// Python interpreter with Pinocchio.
    #[arg(long, default_value = "python3")]
    python: String,
    /// The peer script.
    #[arg(long, default_value = concat!(env!("CARGO_MANIFEST_DIR"), "/../physics/peers/pinocchio_fixtures.py"))]
    script: PathBuf,
}

impl Python {
    fn check(&self) -> Result<()> {
        let ok = Command::new(&self.python)
            .args(["-c", "import pinocchio"])
            .output()
            .map(|o| o.status.success())
            .unwrap_or(false);
        if !ok {
            return Err(crate::exit::PeerMissing(INSTALL.to_string()).into());
        }
        Ok(())
    }

    fn run(&self, args: &[String]) -> Result<String> {
        let out = Command::new(&self.python)
            .arg(&self.script)
            .args(args)
            .output()
            .with_context(|| format!("running {} {}", self.python, self.script.display()))?;
        if !out.status.success() {
            bail!(
                "peer script failed: {}",
                String::from_utf8_lossy(&out.stderr).trim()
            );
        }
        Ok(String::from_utf8(out.stdout)?)
    }
}

fn write_models(dir: &Path, models: &[ModelDescription]) -> Result<Vec<String>> {
    std::fs::create_dir_all(dir)?;
    models
        .iter()
        .map(|m| {
            let p = dir.join(format!("{}.json", m.name));
            std::fs::write(&p, m.to_json())?;
            Ok(p.display().to_string())
        })
        .collect()
}

fn temp_dir() -> PathBuf {
    std::env::temp_dir().join(format!("vphys-peers-{}", std::process::id()))
}

#[derive(Serialize)]
struct Row {
    model: String,
    dofs: usize,
    ours_us: f64,
    pinocchio_us: f64,
    ratio: f64,
}

#[derive(Serialize)]
struct Report {
    pinocchio: String,
    ratio: &'static str,
    rows: Vec<Row>,
}

/// µs per `aba` call of ours, cycling through 256 random states.
fn time_ours(desc: &ModelDescription) -> Result<(usize, f64)> {
    let tree = desc.build::<f64>()?;
    let mut ws = Workspace::new(&tree);
    let states: Vec<_> = (0..256).map(|k| random_state(&tree, 1000 + k)).collect();
    let mut qdd = vec![0.0; tree.nv()];
    let mut k = 0;
    let ns = time_ns(|| {
        let (q, qd, tau) = &states[k];
        k = (k + 1) % states.len();
        aba(&tree, &mut ws, q, qd, tau, None, &mut qdd).expect("aba");
        qdd[0]
    });
    Ok((tree.nv(), ns / 1e3))
}

pub fn run(cmd: PeersCmd) -> Result<()> {
    match cmd {
        PeersCmd::Models { out } => {
            for p in write_models(&out, &peer_models())? {
                outln!("wrote {p}");
            }
        }
        PeersCmd::Fixtures { out, py } => {
            py.check()?;
            let out = out.unwrap_or_else(|| {
                PathBuf::from(concat!(
                    env!("CARGO_MANIFEST_DIR"),
                    "/../physics/tests/fixtures"
                ))
            });
            std::fs::create_dir_all(&out)?;
            let dir = temp_dir();
            let mut args = vec!["fixtures".to_string()];
            args.extend(write_models(&dir, &peer_models())?);
            args.extend(["--out".to_string(), out.display().to_string()]);
            out!("{}", py.run(&args)?);
            std::fs::remove_dir_all(&dir).ok();
        }
        PeersCmd::Rapier {
            json,
            stacks,
            suite: true,
            repeats,
        } => crate::suite::run(stacks.steps, repeats as usize, json)?,
        PeersCmd::Rapier { json, stacks, .. } => {
            crate::rapier_peer::run(&stacks.scenes, stacks.steps, json)?
        }
        PeersCmd::Front {
            json,
            stacks,
            chart,
        } => crate::front::run(&stacks.scenes, stacks.steps, json, chart.as_deref())?,
        PeersCmd::Tumbling {
            json,
            python,
            script,
            chart,
        } => crate::tumbling_peers::run(&python, &script, json, chart.as_deref())?,
        PeersCmd::Multibody { json, steps, scene } => {
            crate::multibody_peer::run(&scene, steps, json)?
        }
        PeersCmd::Parry { json } => crate::parry_peer::run(json)?,
        PeersCmd::Aba { json, py } => {
            py.check()?;
            let models = vec![chain(7), chain(30), chain(100), humanoid()];
            let dir = temp_dir();
            let mut args = vec!["bench".to_string()];
            args.extend(write_models(&dir, &models)?);
            let peer: serde_json::Value = serde_json::from_str(&py.run(&args)?)?;
            std::fs::remove_dir_all(&dir).ok();
            let mut rows = Vec::new();
            for m in &models {
                let (dofs, ours) = time_ours(m)?;
                let theirs = peer["us"][&m.name]
                    .as_f64()
                    .with_context(|| format!("no Pinocchio time for {}", m.name))?;
                rows.push(Row {
                    model: m.name.clone(),
                    dofs,
                    ours_us: ours,
                    pinocchio_us: theirs,
                    ratio: theirs / ours,
                });
            }
            let report = Report {
                pinocchio: peer["pinocchio"].as_str().unwrap_or("?").to_string(),
                ratio: "pinocchio_us / ours_us (> 1: ours is faster)",
                rows,
            };
            if json {
                outln!("{}", serde_json::to_string(&report)?);
            } else {
                outln!(
                    "forward dynamics (ABA), f64, µs per call; Pinocchio {} via abaInParallel(1 thread)",
                    report.pinocchio
                );
                outln!(
                    "{:<10} {:>5} {:>10} {:>15} {:>22}",
                    "model",
                    "dofs",
                    "ours µs",
                    "pinocchio µs",
                    "ratio (pinocchio/ours)"
                );
                for r in &report.rows {
                    outln!(
                        "{:<10} {:>5} {:>10.3} {:>15.3} {:>22.2}",
                        r.model,
                        r.dofs,
                        r.ours_us,
                        r.pinocchio_us,
                        r.ratio
                    );
                }
            }
        }
    }
    Ok(())
}
