//! Try the viewer without the solver.
//!
//! ```text
//! cargo run -p meshfree-viewer --example demo            # live 2D window
//! cargo run -p meshfree-viewer --example demo -- 3d      # live 3D window
//! cargo run -p meshfree-viewer --example demo -- 3d --headless out.png
//! cargo run -p meshfree-viewer --example demo -- 2d --shot out.png   # window, screenshot after 10 frames, close
//! ```

use meshfree_viewer::demo::DemoSource;
use meshfree_viewer::{
    render_headless, run_window, Field, FrameData, LiveSource, RenderOptions, ViewOptions,
};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let three_d = args.iter().any(|a| a == "3d");
    let value_after = |flag: &str| {
        args.iter()
            .position(|a| a == flag)
            .and_then(|i| args.get(i + 1))
            .cloned()
    };
    let mut source = if three_d {
        DemoSource::new_3d(24)
    } else {
        DemoSource::new_2d(64)
    };
    if let Some(path) = value_after("--headless") {
        source.advance(50)?;
        let mut frame = FrameData::default();
        source.frame(Field::Speed, &mut frame);
        let st = source.status();
        let opts = RenderOptions {
            width: 1024,
            height: 768,
            overlay: vec![format!(
                "t {:.4}  step {}  particles {}",
                st.time, st.step, st.particles
            )],
            ..RenderOptions::default()
        };
        render_headless(&frame, &opts)?.save_png(&path)?;
        println!("wrote {path}");
        return Ok(());
    }
    let opts = ViewOptions {
        title: format!(
            "meshfree viewer demo ({})",
            if three_d { "3D" } else { "2D" }
        ),
        screenshot_after_frames: value_after("--shot").map(|p| (10, p.into())),
        ..ViewOptions::default()
    };
    run_window(&mut source, opts)?;
    Ok(())
}
