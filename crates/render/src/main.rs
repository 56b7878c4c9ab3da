//! `render`: the README's main command. Renders the procedural demo scenes through the
//! full pipeline (deferred texturing, the depth-equal baseline, or both), writes the image
//! and its debug views as PNGs, and prints the statistics table. `render --help` lists the
//! options; every value is checked before anything is built.

use clap::Parser;

fn main() -> anyhow::Result<()> {
    render::run(&render::Args::parse())
}
