//! `vibroatlas merge`: reassemble shard files into one atlas ([`engine::merge`]).

use crate::args::MergeArgs;
use crate::common::command_line;
use crate::progress::Shown;
use anyhow::Result;

/// Runs the command.
pub fn run(a: MergeArgs) -> Result<()> {
    let r = engine::MergeRequest {
        parts: a.parts.clone(),
        output: a.output.clone(),
        allow_missing: a.allow_missing,
        command: command_line(),
    };
    engine::merge(&r, &Shown::new("merge", false))?;
    crate::out::line(&format!("merged {} files into {}", a.parts.len(), a.output.display()))
}
