//! Input: window events (egui sees each first and may keep the keyboard or the pointer),
//! the keys' switches and the fly camera's mouse look and movement.

use anyhow::Result;
use gpu::RenderPath;
use gpu::config::{LightPaths, MsaaLighting};
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::ActiveEventLoop;
use winit::keyboard::{KeyCode, PhysicalKey};

use super::{OCCLUSIONS, State};
use crate::Args;
use crate::camera::FlyCamera;
use crate::views::DebugView;

/// Radians the view turns per pixel of mouse motion.
const LOOK_PER_PIXEL: f32 = 0.003;

impl State {
    pub(super) fn window_event(
        &mut self,
        event_loop: &ActiveEventLoop,
        args: &Args,
        event: WindowEvent,
    ) -> Result<()> {
        let response = self.egui_state.on_window_event(&self.window, &event);
        let egui_pointer = self.overlay && self.egui_ctx.egui_wants_pointer_input();
        let egui_keys = self.overlay && self.egui_ctx.egui_wants_keyboard_input();
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::RedrawRequested => self.frame(event_loop, args)?,
            WindowEvent::ModifiersChanged(m) => self.shift = m.state().shift_key(),
            WindowEvent::Focused(false) => {
                self.keys.clear();
                self.looking = false;
            }
            WindowEvent::KeyboardInput { event, .. } => {
                let PhysicalKey::Code(code) = event.physical_key else {
                    return Ok(());
                };
                if event.state == ElementState::Released {
                    self.keys.remove(&code);
                } else if !(egui_keys || response.consumed && code == KeyCode::Tab) {
                    self.keys.insert(code);
                    if !event.repeat {
                        self.key(event_loop, code);
                    }
                }
            }
            WindowEvent::MouseInput { state, button, .. } => {
                if matches!(button, MouseButton::Left | MouseButton::Right) {
                    self.looking = state == ElementState::Pressed && !egui_pointer;
                }
            }
            WindowEvent::CursorMoved { position, .. } => {
                let now = (position.x, position.y);
                if let (true, Some(before)) = (self.looking, self.cursor)
                    && self.script.is_none()
                {
                    let (dx, dy) = ((now.0 - before.0) as f32, (now.1 - before.1) as f32);
                    self.camera.look(dx * LOOK_PER_PIXEL, -dy * LOOK_PER_PIXEL);
                }
                self.cursor = Some(now);
            }
            WindowEvent::CursorLeft { .. } => self.cursor = None,
            WindowEvent::MouseWheel { delta, .. } if !egui_pointer => {
                let steps = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => (p.y / 40.0) as f32,
                };
                self.camera.wheel(steps);
            }
            _ => {}
        }
        Ok(())
    }

    /// A key pressed (not a repeat) that the overlay did not take.
    fn key(&mut self, event_loop: &ActiveEventLoop, code: KeyCode) {
        let digit = [
            KeyCode::Digit0,
            KeyCode::Digit1,
            KeyCode::Digit2,
            KeyCode::Digit3,
            KeyCode::Digit4,
            KeyCode::Digit5,
            KeyCode::Digit6,
            KeyCode::Digit7,
            KeyCode::Digit8,
        ]
        .iter()
        .position(|&k| k == code);
        if let Some(i) = digit {
            self.view = DebugView::ALL[i];
            return;
        }
        match code {
            KeyCode::Escape => event_loop.exit(),
            KeyCode::KeyP => {
                self.path = match self.path {
                    RenderPath::Deferred => RenderPath::Baseline,
                    RenderPath::Baseline => RenderPath::PixelPull,
                    _ => RenderPath::Deferred,
                }
            }
            KeyCode::KeyV => self.view = self.view.cycle(if self.shift { -1 } else { 1 }),
            KeyCode::KeyM => {
                self.wanted.image.msaa = match self.wanted.image.msaa {
                    None => Some(MsaaLighting::Kz2),
                    Some(MsaaLighting::Kz2) => Some(MsaaLighting::EverySample),
                    Some(MsaaLighting::EverySample) => None,
                }
            }
            KeyCode::KeyL => {
                self.wanted.lighting.light_paths = match self.wanted.lighting.light_paths {
                    LightPaths::Tiled => LightPaths::Classified,
                    LightPaths::Classified => LightPaths::Volumes,
                    LightPaths::Volumes => LightPaths::EveryPixel,
                    LightPaths::EveryPixel => LightPaths::Tiled,
                }
            }
            KeyCode::KeyO => {
                self.wanted.lighting.shadows = match self.wanted.lighting.shadows {
                    Some(_) => None,
                    None => Some(gpu::config::ShadowConfig::default()),
                }
            }
            KeyCode::KeyC => {
                if let Some(s) = &mut self.statics {
                    let i = OCCLUSIONS
                        .iter()
                        .position(|(o, _)| *o == s.occlusion)
                        .map_or(0, |i| (i + 1) % OCCLUSIONS.len());
                    s.occlusion = OCCLUSIONS[i].0;
                }
            }
            KeyCode::KeyR => self.camera = FlyCamera::new(self.home),
            KeyCode::F1 => self.overlay = !self.overlay,
            KeyCode::F12 => self.screenshot_requested = true,
            _ => {}
        }
    }

    /// Moves the camera by the held keys over `seconds`.
    pub(super) fn fly(&mut self, seconds: f32) {
        let held = |k: KeyCode| f32::from(u8::from(self.keys.contains(&k)));
        let fast = if self.shift { 4.0 } else { 1.0 };
        self.camera.fly(
            held(KeyCode::KeyD) - held(KeyCode::KeyA),
            held(KeyCode::KeyE) - held(KeyCode::KeyQ),
            held(KeyCode::KeyW) - held(KeyCode::KeyS),
            seconds * fast,
        );
    }
}
