//! The wgpu instance, adapter and device: every backend, the limits asked, the errors
//! the device reports.

use crate::RenderError;

/// A wgpu instance with every backend compiled in.
pub(crate) fn new_instance() -> wgpu::Instance {
    wgpu::Instance::new(&instance_descriptor())
}

fn instance_descriptor() -> wgpu::InstanceDescriptor {
    wgpu::InstanceDescriptor {
        backends: wgpu::Backends::all(),
        ..Default::default()
    }
}

/// A wgpu instance for the page: WebGPU where the browser gives an adapter for it (a
/// `navigator.gpu` without one, as in a browser whose WebGPU is switched off for this
/// GPU, is not enough), else WebGL2, when the embedding crate enables both.
#[cfg(target_arch = "wasm32")]
pub(crate) async fn new_browser_instance() -> wgpu::Instance {
    wgpu::util::new_instance_with_webgpu_detection(&instance_descriptor()).await
}

/// The first adapter that can draw (to `surface` when given: a hardware GPU, else a
/// fallback/software one such as Mesa's lavapipe) and a device on it.
pub(crate) fn open_device(
    instance: &wgpu::Instance,
    surface: Option<&wgpu::Surface<'_>>,
) -> Result<(wgpu::Adapter, wgpu::Device, wgpu::Queue), RenderError> {
    pollster::block_on(open_device_async(instance, surface))
}

/// [`open_device`], awaiting the adapter and the device (in a browser, WebGPU's
/// promises complete only once the page's event loop runs).
pub(crate) async fn open_device_async(
    instance: &wgpu::Instance,
    surface: Option<&wgpu::Surface<'_>>,
) -> Result<(wgpu::Adapter, wgpu::Device, wgpu::Queue), RenderError> {
    let mut opts = wgpu::RequestAdapterOptions {
        power_preference: wgpu::PowerPreference::HighPerformance,
        force_fallback_adapter: false,
        compatible_surface: surface,
    };
    let adapter = match instance.request_adapter(&opts).await {
        Ok(a) => a,
        Err(first) => {
            opts.force_fallback_adapter = true;
            instance
                .request_adapter(&opts)
                .await
                .map_err(|_| RenderError::NoAdapter(first.to_string()))?
        }
    };
    let (device, queue) = adapter
        .request_device(&wgpu::DeviceDescriptor {
            label: Some("foosball-render"),
            required_features: wgpu::Features::empty(),
            required_limits: base_limits().using_resolution(adapter.limits()),
            ..Default::default()
        })
        .await
        .map_err(|e| RenderError::Device(e.to_string()))?;
    Ok((adapter, device, queue))
}

/// Pops the device's error scope and returns the error it caught. Natively the answer
/// is awaited; in a browser it is taken only when it is there at once (WebGL2's always
/// is, WebGPU's arrives later and is not waited for: the page cannot block, so a
/// validation error there goes unreported rather than stopping the game).
pub(crate) fn popped_error(device: &wgpu::Device) -> Option<wgpu::Error> {
    let popped = device.pop_error_scope();
    #[cfg(not(target_arch = "wasm32"))]
    {
        pollster::block_on(popped)
    }
    #[cfg(target_arch = "wasm32")]
    {
        use std::future::Future;
        use std::task::{Context, Poll, Waker};
        let mut popped = std::pin::pin!(popped);
        match popped
            .as_mut()
            .poll(&mut Context::from_waker(Waker::noop()))
        {
            Poll::Ready(e) => e,
            Poll::Pending => None,
        }
    }
}

/// The limits asked of the device: wgpu's downlevel defaults; in a browser WebGL2's
/// (no compute, no storage buffers: the pipelines use neither).
pub(super) fn base_limits() -> wgpu::Limits {
    if cfg!(target_arch = "wasm32") {
        wgpu::Limits::downlevel_webgl2_defaults()
    } else {
        wgpu::Limits::downlevel_defaults()
    }
}
