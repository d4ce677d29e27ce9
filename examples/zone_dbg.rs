use cramp::verify::cases::plates::PlateKind;
fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let f: f64 = args[1].parse()?;
    let dy: f64 = args[2].parse()?;
    let z: f64 = args[3].parse()?;
    let h = 1.0;
    let a = 6.0 + f * h;
    let y0 = -20.0 - 2.0 * h;
    let file = PlateKind::Sent.scene_file(h, a, 0.0).set("grid.origin", format!("[{}, {}]", -2.0 * h, y0 - dy * h)).set("grid.size", format!("[{}, {}]", 20.0 + 4.0 * h, 41.0 + 4.0 * h)).set("solver.tip_zone", z);
    let scene = file.load()?;
    let mut sim = scene.build()?;
    let nsteps: usize = args.get(4).map_or(1, |s| s.parse().unwrap());
    for _ in 0..nsteps { sim.step()?; }
    println!("crack y: {:?}", sim.cracks[0].points.iter().rev().take(4).map(|p| (p.x, p.y)).collect::<Vec<_>>());
    for &nx in &[5.0, 6.0, 7.0] {
        for &ny in &[-dy * h, 1.0 - dy * h] {
            let i = (0..sim.grid.num_nodes()).find(|&i| { let p = sim.grid.node_pos(i); (p.x - nx).abs() < 1e-9 && (p.y - ny).abs() < 1e-9 }).unwrap();
            println!("node ({nx},{ny}) present {:03b}", sim.nodes.present[i]);
            for &it in sim.pairs.of_node(i) {
                let it = it as usize; let pp = it / cramp::shape::MAX_NODES;
                let x = sim.particles.x[pp];
                if sim.pairs.field[it] != 0 || sim.pairs.frac[it] != 1.0 { println!("   p ({:.3},{:.3}) field {} frac {:.3}", x.x, x.y, sim.pairs.field[it], sim.pairs.frac[it]); }
            }
        }
    }
    Ok(())
}
