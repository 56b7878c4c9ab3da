//! Prints the vertex growth of the four primitive-ID encoders on a regular grid, a UV
//! sphere, a random triangle soup and the Stanford bunny, as the markdown table in
//! BENCHMARKS.md: `cargo run -p visbuf --release --example growth` (no arguments).

#[path = "../tests/common/mod.rs"]
mod common;

use clap::Parser;
use common::*;
use visbuf::{
    PrimitiveIdMesh, encode_provoking, encode_provoking_greedy, encode_xor, encode_xor_greedy,
};

type Encoder = fn(&[u32], u32) -> Result<PrimitiveIdMesh, visbuf::Error>;

/// Vertex growth of the primitive-ID encoders on test meshes, as a markdown table.
#[derive(Parser)]
#[command(name = "growth")]
struct Args {}

fn main() {
    Args::parse();
    let (_, bunny_idx) = bunny();
    let meshes: Vec<(&str, Vec<u32>, u32)> = vec![
        {
            let (i, v) = grid(181);
            ("grid 181x181 quads", i, v)
        },
        {
            let (i, v) = uv_sphere(128, 256);
            ("UV sphere 128x256", i, v)
        },
        {
            let (i, v) = soup(65536, 32768, 1);
            ("random soup (V = T/2)", i, v)
        },
        {
            let (i, v) = soup(65536, 3 * 65536 / 4, 2);
            ("random soup (V = 3T/4)", i, v)
        },
        ("Stanford bunny", bunny_idx, 1839),
    ];
    let encoders: [(&str, Encoder); 4] = [
        ("provoking, greedy", encode_provoking_greedy::<u32>),
        ("provoking, matching", encode_provoking::<u32>),
        ("XOR, greedy (talk)", encode_xor_greedy::<u32>),
        ("XOR, peeling", encode_xor::<u32>),
    ];
    print!("| mesh | triangles | vertices | lower bound T - V |");
    for (name, _) in &encoders {
        print!(" {name} |");
    }
    println!();
    println!("|---|---|---|---|---|---|---|---|");
    for (name, idx, vc) in &meshes {
        let t = idx.len() as u32 / 3;
        print!("| {name} | {t} | {vc} | {} |", t.saturating_sub(*vc));
        for (_, enc) in &encoders {
            let m = enc(idx, *vc).expect("valid mesh");
            print!(
                " +{} (+{:.1}%) |",
                m.added_vertices(),
                100.0 * m.added_vertices() as f64 / *vc as f64
            );
        }
        println!();
    }
}
