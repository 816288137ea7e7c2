//! Headless frames: the camera renders into an image, every frame is captured (Bevy's
//! screenshot read-back, the only read-back of a frame) and written as `frame_<n>.png` on a
//! background thread, or kept in memory for tests; wall-clock frame times.

use std::path::PathBuf;
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Instant;

use bevy::camera::RenderTarget;
use bevy::prelude::*;
use bevy::render::render_resource::{TextureFormat, TextureUsages};
use bevy::render::view::screenshot::{Screenshot, ScreenshotCaptured};

/// The image the camera renders into, and where its frames go.
#[derive(Resource, Clone)]
pub struct Capture {
    image: Handle<Image>,
    /// Frame size, pixels.
    pub size: UVec2,
    /// Folder of the PNG files (`None`: none written).
    pub out: Option<PathBuf>,
    /// Keep every frame's pixels in [`Captured`].
    pub keep: bool,
    /// Capture frames (off: render only, e.g. while warming up).
    pub enabled: bool,
}

impl Capture {
    /// The camera's render target.
    pub fn target(&self) -> RenderTarget {
        RenderTarget::Image(self.image.clone().into())
    }
}

/// One captured frame: RGBA8 (sRGB), row-major from the top.
#[derive(Debug, Clone)]
pub struct Frame {
    /// The frame's number (1 = first update).
    pub index: u32,
    /// Width and height, pixels.
    pub size: UVec2,
    /// The pixels.
    pub rgba: Vec<u8>,
}

/// What was captured so far (shared with the capture observers and writer threads).
#[derive(Resource, Clone, Default)]
pub struct Captured {
    frames: Arc<Mutex<Vec<Frame>>>,
    requested: Arc<AtomicU32>,
    finished: Arc<AtomicU32>,
    bytes: Arc<AtomicU32>,
}

impl Captured {
    /// Frames kept in memory ([`Capture::keep`]), in capture order.
    pub fn frames(&self) -> Vec<Frame> {
        self.frames.lock().map(|f| f.clone()).unwrap_or_default()
    }

    /// Whether every requested capture has been read back and written.
    pub fn all_done(&self) -> bool {
        self.finished.load(Ordering::SeqCst) == self.requested.load(Ordering::SeqCst)
    }

    /// Captures finished (read back and written or kept).
    pub fn done(&self) -> u32 {
        self.finished.load(Ordering::SeqCst)
    }

    /// Bytes of frames read back for capture (not part of rendering a dent).
    pub fn readback_bytes(&self) -> u64 {
        u64::from(self.bytes.load(Ordering::SeqCst))
    }
}

/// Wall-clock time between successive frames.
#[derive(Resource, Debug, Default, Clone)]
pub struct FrameClock {
    last: Option<Instant>,
    /// Frames so far.
    pub frame: u32,
    /// Milliseconds between each frame and the one before.
    pub frame_ms: Vec<f64>,
}

impl FrameClock {
    /// The median frame time, ms (0 without frames).
    pub fn median_ms(&self) -> f64 {
        let mut ms = self.frame_ms.clone();
        ms.sort_by(f64::total_cmp);
        ms.get(ms.len() / 2).copied().unwrap_or(0.0)
    }
}

/// Renders into a `size` image and captures every frame (to `out` and/or memory).
pub struct CapturePlugin {
    /// Frame size, pixels.
    pub size: UVec2,
    /// Folder for `frame_<n>.png` files.
    pub out: Option<PathBuf>,
    /// Keep frames in memory.
    pub keep: bool,
}

impl Plugin for CapturePlugin {
    fn build(&self, app: &mut App) {
        let mut image = Image::new_target_texture(self.size.x, self.size.y, TextureFormat::Rgba8UnormSrgb, None);
        image.texture_descriptor.usage |= TextureUsages::COPY_SRC;
        let image = app.world_mut().resource_mut::<Assets<Image>>().add(image);
        let capture = Capture { image, size: self.size, out: self.out.clone(), keep: self.keep, enabled: true };
        app.insert_resource(capture)
            .init_resource::<Captured>()
            .init_resource::<FrameClock>()
            .add_systems(First, tick)
            .add_systems(Last, capture_frame);
    }
}

fn tick(mut clock: ResMut<FrameClock>) {
    let now = Instant::now();
    if let Some(last) = clock.last {
        clock.frame_ms.push((now - last).as_secs_f64() * 1e3);
    }
    clock.last = Some(now);
    clock.frame += 1;
}

fn capture_frame(mut commands: Commands, capture: Res<Capture>, captured: Res<Captured>, clock: Res<FrameClock>) {
    if !capture.enabled {
        return;
    }
    captured.requested.fetch_add(1, Ordering::SeqCst);
    let (index, out, keep, captured) = (clock.frame, capture.out.clone(), capture.keep, captured.clone());
    commands.spawn(Screenshot::image(capture.image.clone())).observe(move |shot: On<ScreenshotCaptured>| {
        let done = captured.clone();
        let Ok(rgba) = shot.image.clone().try_into_dynamic().map(|d| d.into_rgba8()) else {
            warn!("headless capture: frame {index} has an unexpected format");
            done.finished.fetch_add(1, Ordering::SeqCst);
            return;
        };
        done.bytes.fetch_add(rgba.as_raw().len() as u32, Ordering::SeqCst);
        if keep && let Ok(mut frames) = done.frames.lock() {
            frames.push(Frame { index, size: UVec2::new(rgba.width(), rgba.height()), rgba: rgba.as_raw().clone() });
        }
        let out = out.clone();
        std::thread::spawn(move || {
            if let Some(dir) = out {
                let path = dir.join(format!("frame_{index}.png"));
                if let Err(e) = rgba.save(&path) {
                    error!("headless capture: {} could not be written ({e})", path.display());
                }
            }
            done.finished.fetch_add(1, Ordering::SeqCst);
        });
    });
}
