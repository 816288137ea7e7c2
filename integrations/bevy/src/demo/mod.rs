//! The scenes of the examples, tests and benchmarks: balls raining on a dentable block, the
//! bunny, a breakable wall and a bendable plank (bevy_rapier3d or Avian contacts), rendered
//! headless into PNG files or windowed.

mod capture;
mod physics;
mod rain;
mod summary;

pub use capture::{Capture, CapturePlugin, Captured, Frame, FrameClock};
pub use physics::Physics;
pub use rain::{RainPlugin, RainSettings, Target, headless_app, headless_app_with};
pub use summary::Summary;
