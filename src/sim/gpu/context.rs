//! Finding a GPU: a wgpu adapter on Vulkan, Metal or DX12, loaded at run time.

use std::future::Future;
use std::pin::pin;
use std::task::{Context, Poll, Waker};

/// Run a wgpu future to completion on this thread. wgpu's native futures are ready when first
/// polled, or become ready as the device is polled, so spinning with a no-op waker is enough.
pub(crate) fn block_on<F: Future>(future: F) -> F::Output {
    let mut future = pin!(future);
    let mut context = Context::from_waker(Waker::noop());
    loop {
        if let Poll::Ready(value) = future.as_mut().poll(&mut context) {
            return value;
        }
        std::thread::yield_now();
    }
}

/// The native backends tried (no GL, no WebGPU).
const BACKENDS: wgpu::Backends = wgpu::Backends::VULKAN
    .union(wgpu::Backends::METAL)
    .union(wgpu::Backends::DX12);

/// Standard error silenced while the drivers are probed, restored when dropped. Vulkan drivers
/// print to it themselves: Mesa's window-system code says "error: XDG_RUNTIME_DIR is invalid or
/// not set in the environment" on every instance without a desktop session (a cluster node, a
/// container), which a run that then succeeds must not show. Our own failures are returned as
/// values and printed after; wgpu reports through `log`, which is not printed.
struct QuietStderr {
    #[cfg(unix)]
    saved: Option<std::os::fd::OwnedFd>,
}

impl QuietStderr {
    #[cfg(unix)]
    fn new() -> QuietStderr {
        use rustix::fs::{Mode, OFlags};
        let saved = (|| {
            let saved = rustix::io::dup(rustix::stdio::stderr()).ok()?;
            let null =
                rustix::fs::open("/dev/null", OFlags::WRONLY | OFlags::CLOEXEC, Mode::empty())
                    .ok()?;
            rustix::stdio::dup2_stderr(&null).ok()?;
            Some(saved)
        })();
        QuietStderr { saved }
    }

    #[cfg(not(unix))]
    fn new() -> QuietStderr {
        QuietStderr {}
    }
}

impl Drop for QuietStderr {
    fn drop(&mut self) {
        #[cfg(unix)]
        if let Some(saved) = self.saved.take() {
            let _ = rustix::stdio::dup2_stderr(&saved);
        }
    }
}

/// An open GPU: the device and its queue.
pub struct Gpu {
    pub(crate) device: wgpu::Device,
    pub(crate) queue: wgpu::Queue,
    pub(crate) limits: wgpu::Limits,
    info: wgpu::AdapterInfo,
}

impl std::fmt::Debug for Gpu {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Gpu")
            .field("adapter", &self.description())
            .finish()
    }
}

impl Gpu {
    /// Open the best GPU: a discrete one first, then an integrated one, then (only when
    /// `accept_software`) a software driver such as Mesa's lavapipe. The error says why none
    /// was usable (no driver, no adapter, only a software one, device creation failed).
    pub fn open(accept_software: bool) -> Result<Gpu, String> {
        let _quiet = QuietStderr::new();
        let mut descriptor = wgpu::InstanceDescriptor::new_without_display_handle();
        descriptor.backends = BACKENDS;
        descriptor.flags = wgpu::InstanceFlags::empty();
        let instance = wgpu::Instance::new(descriptor);
        let adapters = block_on(instance.enumerate_adapters(BACKENDS));
        if adapters.is_empty() {
            return Err(
                "no GPU adapter (no Vulkan, Metal or DX12 driver found; on Linux install the \
                 GPU's Vulkan driver, or Mesa's lavapipe for a software one)"
                    .to_string(),
            );
        }
        let rank = |info: &wgpu::AdapterInfo| match info.device_type {
            wgpu::DeviceType::DiscreteGpu => 0,
            wgpu::DeviceType::IntegratedGpu => 1,
            wgpu::DeviceType::VirtualGpu => 2,
            wgpu::DeviceType::Other => 3,
            wgpu::DeviceType::Cpu => 4,
        };
        let best = adapters
            .into_iter()
            .min_by_key(|adapter| rank(&adapter.get_info()))
            .expect("adapters is not empty");
        let info = best.get_info();
        if info.device_type == wgpu::DeviceType::Cpu && !accept_software {
            return Err(format!(
                "only a software GPU driver ({}) is available",
                info.name
            ));
        }
        let limits = best.limits();
        let (device, queue) = block_on(best.request_device(&wgpu::DeviceDescriptor {
            label: Some("contactmap"),
            required_features: wgpu::Features::empty(),
            required_limits: limits.clone(),
            experimental_features: wgpu::ExperimentalFeatures::disabled(),
            memory_hints: wgpu::MemoryHints::Performance,
            trace: wgpu::Trace::Off,
        }))
        .map_err(|err| format!("cannot open the GPU {}: {err}", info.name))?;
        Ok(Gpu {
            device,
            queue,
            limits,
            info,
        })
    }

    /// The adapter in words, e.g. `NVIDIA H100 80GB HBM3 (Vulkan, discrete GPU)`.
    pub fn description(&self) -> String {
        let kind = match self.info.device_type {
            wgpu::DeviceType::DiscreteGpu => "discrete GPU",
            wgpu::DeviceType::IntegratedGpu => "integrated GPU",
            wgpu::DeviceType::VirtualGpu => "virtual GPU",
            wgpu::DeviceType::Cpu => "software driver",
            wgpu::DeviceType::Other => "GPU",
        };
        format!("{} ({:?}, {kind})", self.info.name, self.info.backend)
    }

    /// Whether this is a software driver running on the CPU (lavapipe, SwiftShader).
    pub fn is_software(&self) -> bool {
        self.info.device_type == wgpu::DeviceType::Cpu
    }
}
