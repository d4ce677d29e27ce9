use cramp::verify::scene_file::SceneFile;
fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().collect();
    let mut f = SceneFile::new("traction_bending.toml");
    for a in &args[1..] { let (k, v) = a.split_once('=').unwrap(); f = f.set(k, v); }
    let scene = f.load()?;
    let mut sim = scene.build()?;
    sim.run_until(scene.solver.end_time, |_| {})?;
    let p = &sim.particles;
    let mut rows: std::collections::BTreeMap<i64, (f64, f64, f64, usize)> = Default::default();
    for i in 0..p.len() {
        if p.x0[i].x < 4.0 || p.x0[i].x > 12.0 { continue; }
        let e = rows.entry((p.x0[i].y * 1000.0) as i64).or_default();
        e.0 += p.stress[i].xx - p.x0[i].y / 2.0; e.1 = e.1.max((p.stress[i].xx - p.x0[i].y / 2.0).abs()); e.2 = e.2.max(p.stress[i].xy.abs().max(p.stress[i].yy.abs())); e.3 += 1;
    }
    for (y, (s, m, o, n)) in rows { println!("y = {:7.3}: mean err {:+.3e}, max err {:.3e}, max |syy|,|sxy| {:.3e}", y as f64 / 1000.0, s / n as f64, m, o); }
    let e = sim.energies(); println!("KE/SE {:.2e}", e.kinetic / e.strain);
    Ok(())
}
