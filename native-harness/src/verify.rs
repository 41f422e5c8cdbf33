//! `meshflow verify --golden DIR`: runs the golden `vae_small` and `dit_small` through this
//! build on the chosen backend and prints the largest difference per tensor, so a new machine
//! or GPU driver can be checked against the reference numerics (tolerance 1e-4). The
//! comparison itself is [`meshflow::model::golden`].

use std::path::PathBuf;

use anyhow::{Result, bail};
use clap::Args;
use meshflow::model::golden::{TOLERANCE, verify};

use crate::args::BackendArg;

/// `meshflow verify`'s arguments.
#[derive(Args)]
pub struct VerifyArgs {
    /// Folder with vae_small.safetensors and dit_small.safetensors.
    #[arg(long)]
    golden: PathBuf,
    #[command(flatten)]
    backend: BackendArg,
}

/// Prints every compared tensor; fails when one is over the tolerance.
pub fn run(args: VerifyArgs) -> Result<()> {
    let kind = args.backend.kind;
    let device = args.backend.device()?;
    let mut failed = 0;
    for report in verify(&args.golden, &device)? {
        for t in report.tensors {
            failed += !t.ok() as usize;
            println!(
                "{:10} {:28} max abs diff {:.2e} {}",
                report.model,
                t.name,
                t.max_abs_diff,
                if t.ok() { "ok" } else { "FAIL" }
            );
        }
    }
    if failed > 0 {
        bail!(
            "{failed} tensor(s) differ from the reference by {TOLERANCE} or more on {}",
            kind.name()
        );
    }
    println!(
        "all tensors within {TOLERANCE:e} of the reference on {}",
        kind.name()
    );
    Ok(())
}
