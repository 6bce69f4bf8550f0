//! Vulkan instance, physical-device selection, logical device, queue, and the collection of
//! validation-layer messages. One [`Context`] is shared (`Arc`) by every object made from it.
//!
//! Validation messages are stored in the context (not a global), because `cargo test` runs tests
//! as threads in one process and each test must see only its own messages.
use std::ffi::{c_char, c_void, CStr};
use std::sync::{Arc, Mutex};

use ash::vk;

use super::conv::VkContext;
use crate::error::{Error, Result};

const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

/// How to create a [`Context`].
#[derive(Debug, Clone, Default)]
pub struct ContextDesc {
    /// Case-insensitive substring of the device name to pick. `None` picks lavapipe
    /// (a CPU-type device, "llvmpipe").
    pub device: Option<String>,
    /// Enable the Khronos validation layer and collect its messages.
    pub validate: bool,
}

/// What the selected device is, for reports.
#[derive(Debug, Clone, serde::Serialize)]
pub struct DeviceInfo {
    pub name: String,
    pub device_type: String,
    pub api_version: String,
    pub driver_name: String,
    pub driver_info: String,
    pub max_image_dimension_2d: u32,
    pub timestamp_period_ns: f32,
    pub timestamp_valid_bits: u32,
    /// Whether pipeline-statistics queries are supported (and enabled on the device).
    pub pipeline_statistics: bool,
    /// Whether float16 arithmetic in shaders (`shaderFloat16`, Vulkan 1.2) is supported (and
    /// then enabled on the device): the float16 programs need it. Not in the outputs' device
    /// record (their `precision` says what ran).
    #[serde(skip)]
    pub shader_float16: bool,
}

/// Messages the validation layer reported, shared with the debug callback.
type MessageLog = Mutex<Vec<String>>;

/// The debug-utils loader and messenger, present when validating.
type Debug = Option<(ash::ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)>;

/// The shared Vulkan context: instance, device, one graphics queue and its command pool.
pub struct Context {
    /// Keeps libvulkan loaded for as long as the context lives.
    _entry: ash::Entry,
    pub(crate) instance: ash::Instance,
    pub(crate) device: ash::Device,
    /// The selected physical device (format and image-format queries).
    pub(crate) physical: vk::PhysicalDevice,
    pub(crate) queue: vk::Queue,
    pub(crate) command_pool: vk::CommandPool,
    pub(crate) memory_properties: vk::PhysicalDeviceMemoryProperties,
    info: DeviceInfo,
    debug: Debug,
    /// Heap-allocated so its address, handed to the layer as user data, never moves.
    messages: Arc<MessageLog>,
    /// Serialises queue submissions (the queue is externally synchronised in Vulkan).
    pub(crate) queue_lock: Mutex<()>,
    /// VK_KHR_pipeline_executable_properties, when the context was made by
    /// [`Context::for_executables`]: pipelines are then created with the capture flags.
    pub(crate) executables: Option<ash::khr::pipeline_executable_properties::Device>,
}

impl Context {
    /// The queue (and command pool) lock. A poisoned lock (another thread panicked while
    /// holding it) is an error, never ignored: the queue's state is then unknown.
    pub(crate) fn lock_queue(&self) -> Result<std::sync::MutexGuard<'_, ()>> {
        self.queue_lock.lock().map_err(|_| {
            Error::Device(
                "the Vulkan queue lock is poisoned: another thread panicked while submitting"
                    .into(),
            )
        })
    }

    /// Loads the Vulkan loader, creates an instance (with validation when asked), picks a device
    /// and creates it with dynamic rendering and synchronization2.
    pub fn new(desc: &ContextDesc) -> Result<Arc<Self>> {
        Context::create(desc, false)
    }

    /// [`Context::new`] with VK_KHR_pipeline_executable_properties and its
    /// `pipelineExecutableInfo` feature: every pipeline made from this context is created with
    /// the CAPTURE_STATISTICS and CAPTURE_INTERNAL_REPRESENTATIONS flags, so that its compiler
    /// statistics and disassembly can be read back (`shadelab isa`, on RADV's null device).
    /// An error when the device lacks the extension.
    pub fn for_executables(desc: &ContextDesc) -> Result<Arc<Self>> {
        Context::create(desc, true)
    }

    /// An error (exit 2) when `precision` needs a device feature this device lacks: float16
    /// programs need `shaderFloat16`.
    pub fn require_precision(&self, precision: crate::method::Precision) -> Result<()> {
        if precision == crate::method::Precision::F16 && !self.info.shader_float16 {
            return Err(Error::Device(format!(
                "--precision f16: {} does not support float16 shader arithmetic \
                 (VkPhysicalDeviceVulkan12Features::shaderFloat16 is false)",
                self.info.name
            )));
        }
        Ok(())
    }

    /// Whether pipelines made from this context capture their statistics and internal
    /// representations.
    pub fn captures_executables(&self) -> bool {
        self.executables.is_some()
    }

    /// The creation flags of every pipeline: the capture flags on a [`Context::for_executables`]
    /// context, none otherwise.
    pub(crate) fn pipeline_flags(&self) -> vk::PipelineCreateFlags {
        if self.executables.is_some() {
            vk::PipelineCreateFlags::CAPTURE_STATISTICS_KHR
                | vk::PipelineCreateFlags::CAPTURE_INTERNAL_REPRESENTATIONS_KHR
        } else {
            vk::PipelineCreateFlags::empty()
        }
    }

    fn create(desc: &ContextDesc, capture: bool) -> Result<Arc<Self>> {
        // SAFETY: loading libvulkan.so.1 runs its initialisers; the loader is a trusted system
        // library and the Entry keeps it loaded for as long as the context lives.
        let entry = unsafe { ash::Entry::load() }.map_err(|e| {
            Error::Device(format!(
                "cannot load the Vulkan loader (libvulkan.so.1): {e}; install libvulkan1 and \
                 mesa-vulkan-drivers (scripts/install-deps.sh run)"
            ))
        })?;

        let messages: Arc<MessageLog> = Arc::new(Mutex::new(Vec::new()));
        let app_name = c"shadelab";
        let app = vk::ApplicationInfo::default()
            .application_name(app_name)
            .engine_name(app_name)
            .api_version(vk::API_VERSION_1_3);
        let (layers, extensions) = instance_layers(&entry, desc.validate)?;
        let user_data = Arc::as_ptr(&messages) as *mut c_void;
        let mut messenger_info = vk::DebugUtilsMessengerCreateInfoEXT::default()
            .message_severity(
                vk::DebugUtilsMessageSeverityFlagsEXT::WARNING
                    | vk::DebugUtilsMessageSeverityFlagsEXT::ERROR,
            )
            .message_type(
                vk::DebugUtilsMessageTypeFlagsEXT::GENERAL
                    | vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                    | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
            )
            .pfn_user_callback(Some(debug_callback))
            .user_data(user_data);
        let mut instance_info = vk::InstanceCreateInfo::default()
            .application_info(&app)
            .enabled_layer_names(&layers)
            .enabled_extension_names(&extensions);
        if desc.validate {
            // Chained so that messages from vkCreateInstance itself are collected too.
            instance_info = instance_info.push_next(&mut messenger_info);
        }
        // SAFETY: every pointer in instance_info refers to locals that outlive the call.
        let instance =
            unsafe { entry.create_instance(&instance_info, None) }.map_err(|r| match r {
                vk::Result::ERROR_INCOMPATIBLE_DRIVER => Error::Device(
                    "no Vulkan 1.3 driver found: install mesa-vulkan-drivers (lavapipe)".into(),
                ),
                r => Error::Vulkan {
                    call: "vkCreateInstance",
                    result: format!("{r:?}"),
                },
            })?;
        // From here on, `instance` must be destroyed on error paths: build the rest in a guard.
        let guard = InstanceGuard {
            instance: Some(instance),
        };

        let debug = if desc.validate {
            let loader = ash::ext::debug_utils::Instance::new(&entry, guard.get());
            // SAFETY: messenger_info's user data points into `messages`, which the context owns
            // and outlives the messenger (destroyed first in Drop).
            let m = unsafe { loader.create_debug_utils_messenger(&messenger_info, None) }
                .vk("vkCreateDebugUtilsMessengerEXT")?;
            Some((loader, m))
        } else {
            None
        };

        let (physical, info, queue_family) =
            match select_device(guard.get(), desc.device.as_deref()) {
                Ok(v) => v,
                Err(e) => {
                    if let Some((loader, m)) = &debug {
                        // SAFETY: the messenger was created above from this instance.
                        unsafe { loader.destroy_debug_utils_messenger(*m, None) };
                    }
                    return Err(e);
                }
            };

        let instance = guard.get();
        let (device, queue, command_pool) =
            create_device(instance, physical, &info, queue_family, &debug, capture)?;
        // SAFETY: plain query.
        let memory_properties = unsafe { instance.get_physical_device_memory_properties(physical) };
        let executables = capture
            .then(|| ash::khr::pipeline_executable_properties::Device::new(instance, &device));
        let instance = guard.release();
        Ok(Arc::new(Context {
            executables,
            _entry: entry,
            instance,
            device,
            physical,
            queue,
            command_pool,
            memory_properties,
            info,
            debug,
            messages,
            queue_lock: Mutex::new(()),
        }))
    }

    /// The selected device, for reports and limits.
    pub fn info(&self) -> &DeviceInfo {
        &self.info
    }

    /// Validation messages collected so far (empty when validation is off).
    pub fn validation_messages(&self) -> Vec<String> {
        self.messages.lock().map(|m| m.clone()).unwrap_or_default()
    }

    /// Whether the validation layer is active on this context.
    pub fn validating(&self) -> bool {
        self.debug.is_some()
    }

    /// Whether a `width` x `height` image of `format` with LINEAR tiling can be a colour
    /// attachment (`linearTilingFeatures` has COLOR_ATTACHMENT and the image-format limits
    /// allow the size): a render target the host can then read in place
    /// ([`super::ImageUsage::HostColorTarget`]).
    pub fn linear_color_target(&self, format: super::Format, width: u32, height: u32) -> bool {
        let i = &self.instance;
        // SAFETY: plain queries on the context's own physical device.
        let features =
            unsafe { i.get_physical_device_format_properties(self.physical, format.raw()) };
        if !features
            .linear_tiling_features
            .contains(vk::FormatFeatureFlags::COLOR_ATTACHMENT)
        {
            return false;
        }
        // SAFETY: as above.
        let limits = unsafe {
            i.get_physical_device_image_format_properties(
                self.physical,
                format.raw(),
                vk::ImageType::TYPE_2D,
                vk::ImageTiling::LINEAR,
                super::ImageUsage::HostColorTarget.raw(),
                vk::ImageCreateFlags::empty(),
            )
        };
        limits.is_ok_and(|l| l.max_extent.width >= width && l.max_extent.height >= height)
    }

    /// The size of the device's largest device-local memory heap, bytes.
    pub fn heap_bytes(&self) -> u64 {
        let p = &self.memory_properties;
        p.memory_heaps[..p.memory_heap_count as usize]
            .iter()
            .filter(|h| h.flags.contains(vk::MemoryHeapFlags::DEVICE_LOCAL))
            .map(|h| h.size)
            .max()
            .unwrap_or(0)
    }

    /// Checks an image size against the device limit and a draw's memory against the
    /// device's heap and the machine's memory ([`crate::memory::DRAW`]), before any image is
    /// allocated. Errors are usage errors (exit 2).
    pub fn check_image_size(&self, width: u32, height: u32) -> Result<()> {
        let max = self.info.max_image_dimension_2d;
        if width == 0 || height == 0 {
            return Err(Error::Usage(format!(
                "image size {width}x{height} is empty: width and height must be at least 1"
            )));
        }
        if width > max || height > max {
            return Err(Error::Usage(format!(
                "image size {width}x{height} exceeds the device's maxImageDimension2D ({max}) on {}",
                self.info.name
            )));
        }
        let heap = Some(self.heap_bytes()).filter(|&h| h > 0);
        crate::memory::check(&crate::memory::DRAW, width, height, heap)
    }

    /// Names and types of every device the loader reports (for `--device` errors and `shadelab devices`).
    pub fn list_devices() -> Result<Vec<String>> {
        // SAFETY: as in `new`.
        let entry = unsafe { ash::Entry::load() }
            .map_err(|e| Error::Device(format!("cannot load libvulkan.so.1: {e}")))?;
        let app = vk::ApplicationInfo::default().api_version(vk::API_VERSION_1_3);
        let info = vk::InstanceCreateInfo::default().application_info(&app);
        // SAFETY: info references locals only.
        let instance = unsafe { entry.create_instance(&info, None) }.vk("vkCreateInstance")?;
        let guard = InstanceGuard {
            instance: Some(instance),
        };
        device_names(guard.get())
    }
}

/// The instance layers and extensions [`Context::new`] enables: the Khronos validation layer and
/// debug utils when `validate`, an error when that layer is not installed; none otherwise.
fn instance_layers(
    entry: &ash::Entry,
    validate: bool,
) -> Result<(Vec<*const c_char>, Vec<*const c_char>)> {
    let mut layers: Vec<*const c_char> = Vec::new();
    let mut extensions: Vec<*const c_char> = Vec::new();
    if validate {
        // SAFETY: plain query of instance layer properties.
        let available = unsafe { entry.enumerate_instance_layer_properties() }
            .vk("vkEnumerateInstanceLayerProperties")?;
        let found = available.iter().any(|l| {
            l.layer_name_as_c_str()
                .map(|n| n == VALIDATION_LAYER)
                .unwrap_or(false)
        });
        if !found {
            return Err(Error::Device(
                "--validate: the Khronos validation layer (VK_LAYER_KHRONOS_validation) is not \
                 installed; install vulkan-validationlayers (scripts/install-deps.sh test)"
                    .into(),
            ));
        }
        layers.push(VALIDATION_LAYER.as_ptr());
        extensions.push(ash::ext::debug_utils::NAME.as_ptr());
    }
    Ok((layers, extensions))
}

/// The logical device of [`Context::new`] (dynamic rendering, synchronization2, maintenance4,
/// pipeline statistics when supported), its queue and command pool. On error, what was created
/// here and the debug messenger are destroyed (the caller's guard destroys the instance).
fn create_device(
    instance: &ash::Instance,
    physical: vk::PhysicalDevice,
    info: &DeviceInfo,
    queue_family: u32,
    debug: &Debug,
    capture: bool,
) -> Result<(ash::Device, vk::Queue, vk::CommandPool)> {
    let priorities = [1.0f32];
    let queue_info = [vk::DeviceQueueCreateInfo::default()
        .queue_family_index(queue_family)
        .queue_priorities(&priorities)];
    let mut f13 = vk::PhysicalDeviceVulkan13Features::default()
        .dynamic_rendering(true)
        .synchronization2(true)
        .maintenance4(true);
    // Only when supported: requesting it on a device without it fails device creation (RADV's
    // polaris10 null device, ../shared/TOOLCHAIN.md).
    let mut f12 = vk::PhysicalDeviceVulkan12Features::default().shader_float16(info.shader_float16);
    let core =
        vk::PhysicalDeviceFeatures::default().pipeline_statistics_query(info.pipeline_statistics);
    let capture_ext = [ash::khr::pipeline_executable_properties::NAME.as_ptr()];
    let mut capture_feature = vk::PhysicalDevicePipelineExecutablePropertiesFeaturesKHR::default()
        .pipeline_executable_info(true);
    let mut device_info = vk::DeviceCreateInfo::default()
        .queue_create_infos(&queue_info)
        .enabled_features(&core)
        .push_next(&mut f13)
        .push_next(&mut f12);
    if capture {
        // VK_KHR_pipeline_executable_properties (a capture context, `shadelab isa`).
        device_info = device_info
            .enabled_extension_names(&capture_ext)
            .push_next(&mut capture_feature);
    }
    // SAFETY: physical belongs to instance; the create info references locals only.
    let device = unsafe { instance.create_device(physical, &device_info, None) };
    let device = match device {
        Ok(d) => d,
        Err(r) => {
            if let Some((loader, m)) = debug {
                // SAFETY: created by the caller from this instance and not yet destroyed.
                unsafe { loader.destroy_debug_utils_messenger(*m, None) };
            }
            return Err(Error::Vulkan {
                call: "vkCreateDevice",
                result: format!("{r:?}"),
            });
        }
    };
    // SAFETY: queue family and index 0 were requested at device creation.
    let queue = unsafe { device.get_device_queue(queue_family, 0) };
    let pool_info = vk::CommandPoolCreateInfo::default()
        .queue_family_index(queue_family)
        .flags(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
    // SAFETY: valid device.
    let command_pool = unsafe { device.create_command_pool(&pool_info, None) };
    let command_pool = match command_pool {
        Ok(p) => p,
        Err(r) => {
            // SAFETY: nothing else was created from the device yet.
            unsafe { device.destroy_device(None) };
            if let Some((loader, m)) = debug {
                // SAFETY: as above.
                unsafe { loader.destroy_debug_utils_messenger(*m, None) };
            }
            return Err(Error::Vulkan {
                call: "vkCreateCommandPool",
                result: format!("{r:?}"),
            });
        }
    };
    Ok((device, queue, command_pool))
}

/// Destroys an instance on early return during [`Context::new`].
struct InstanceGuard {
    instance: Option<ash::Instance>,
}

impl InstanceGuard {
    fn get(&self) -> &ash::Instance {
        self.instance
            .as_ref()
            .expect("instance present until released")
    }
    fn release(mut self) -> ash::Instance {
        self.instance
            .take()
            .expect("instance present until released")
    }
}

impl Drop for InstanceGuard {
    fn drop(&mut self) {
        if let Some(i) = self.instance.take() {
            // SAFETY: no child object of the instance survives an early return.
            unsafe { i.destroy_instance(None) };
        }
    }
}

fn device_name(props: &vk::PhysicalDeviceProperties) -> String {
    props
        .device_name_as_c_str()
        .map(|c| c.to_string_lossy().into_owned())
        .unwrap_or_default()
}

fn device_names(instance: &ash::Instance) -> Result<Vec<String>> {
    // SAFETY: plain queries on a live instance.
    let devices =
        unsafe { instance.enumerate_physical_devices() }.vk("vkEnumeratePhysicalDevices")?;
    Ok(devices
        .iter()
        .map(|&d| {
            // SAFETY: d comes from this instance.
            let p = unsafe { instance.get_physical_device_properties(d) };
            format!("{} ({:?})", device_name(&p), p.device_type)
        })
        .collect())
}

fn select_device(
    instance: &ash::Instance,
    filter: Option<&str>,
) -> Result<(vk::PhysicalDevice, DeviceInfo, u32)> {
    // SAFETY: plain query on a live instance.
    let devices =
        unsafe { instance.enumerate_physical_devices() }.vk("vkEnumeratePhysicalDevices")?;
    if devices.is_empty() {
        return Err(Error::Device(
            "no Vulkan device found: install mesa-vulkan-drivers (lavapipe, a CPU Vulkan driver)"
                .into(),
        ));
    }
    let mut seen = Vec::new();
    let mut chosen = None;
    for &d in &devices {
        // SAFETY: d comes from this instance.
        let props = unsafe { instance.get_physical_device_properties(d) };
        let name = device_name(&props);
        seen.push(format!("{name} ({:?})", props.device_type));
        let matches = match filter {
            Some(f) => name.to_lowercase().contains(&f.to_lowercase()),
            None => props.device_type == vk::PhysicalDeviceType::CPU || name.contains("llvmpipe"),
        };
        if matches && chosen.is_none() {
            chosen = Some((d, props));
        }
    }
    let Some((physical, props)) = chosen else {
        let wanted = match filter {
            Some(f) => format!("no Vulkan device name contains {f:?}"),
            None => "no lavapipe (llvmpipe) device found; install mesa-vulkan-drivers or pick \
                     another with --device SUBSTRING"
                .to_string(),
        };
        return Err(Error::Device(format!(
            "{wanted}; devices found: {}",
            seen.join(", ")
        )));
    };
    // SAFETY: plain query.
    let families = unsafe { instance.get_physical_device_queue_family_properties(physical) };
    let queue_family = families
        .iter()
        .position(|f| f.queue_flags.contains(vk::QueueFlags::GRAPHICS))
        .ok_or_else(|| Error::Device(format!("{} has no graphics queue", device_name(&props))))?
        as u32;
    let mut driver = vk::PhysicalDeviceDriverProperties::default();
    let mut props2 = vk::PhysicalDeviceProperties2::default().push_next(&mut driver);
    // SAFETY: props2 chain references locals only; Vulkan 1.1+ core query.
    unsafe { instance.get_physical_device_properties2(physical, &mut props2) };
    let cstr = |c: Result<&CStr, _>| -> String {
        c.map(|c: &CStr| c.to_string_lossy().into_owned())
            .unwrap_or_default()
    };
    let mut f12 = vk::PhysicalDeviceVulkan12Features::default();
    let mut features2 = vk::PhysicalDeviceFeatures2::default().push_next(&mut f12);
    // SAFETY: the chain references locals only; Vulkan 1.1+ core query.
    unsafe { instance.get_physical_device_features2(physical, &mut features2) };
    let shader_float16 = f12.shader_float16 == vk::TRUE;
    let v = props.api_version;
    let info = DeviceInfo {
        name: device_name(&props),
        device_type: format!("{:?}", props.device_type),
        api_version: format!(
            "{}.{}.{}",
            vk::api_version_major(v),
            vk::api_version_minor(v),
            vk::api_version_patch(v)
        ),
        driver_name: cstr(driver.driver_name_as_c_str().map_err(|_| ())),
        driver_info: cstr(driver.driver_info_as_c_str().map_err(|_| ())),
        max_image_dimension_2d: props.limits.max_image_dimension2_d,
        timestamp_period_ns: props.limits.timestamp_period,
        timestamp_valid_bits: families[queue_family as usize].timestamp_valid_bits,
        // SAFETY: plain query.
        pipeline_statistics: unsafe { instance.get_physical_device_features(physical) }
            .pipeline_statistics_query
            == vk::TRUE,
        shader_float16,
    };
    if vk::api_version_minor(v) < 3 && vk::api_version_major(v) == 1 {
        return Err(Error::Device(format!(
            "{} supports Vulkan {}, shadelab needs 1.3 (dynamic rendering)",
            info.name, info.api_version
        )));
    }
    Ok((physical, info, queue_family))
}

/// Collects validation messages into the context's log.
unsafe extern "system" fn debug_callback(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    _types: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user: *mut c_void,
) -> vk::Bool32 {
    if data.is_null() || user.is_null() {
        return vk::FALSE;
    }
    // SAFETY: the layer passes a valid callback-data struct for the duration of the call, and
    // `user` is the `MessageLog` the context holds in an Arc, alive while the messenger is.
    let (data, log) = unsafe { (&*data, &*(user as *const MessageLog)) };
    // SAFETY: p_message is a NUL-terminated string owned by the layer for this call.
    let text = unsafe { data.message_as_c_str() }
        .map(|c| c.to_string_lossy().into_owned())
        .unwrap_or_default();
    if let Ok(mut m) = log.lock() {
        m.push(format!("[{severity:?}] {text}"));
    }
    vk::FALSE
}

impl Drop for Context {
    fn drop(&mut self) {
        // SAFETY: every object made from the device holds an Arc<Context>, so all are gone;
        // no work is in flight (synchronous submits). Destroy in reverse creation order.
        unsafe {
            // A capture context never submits (RADV's null device, whose queue has no wait:
            // vkDeviceWaitIdle jumps to a null pointer there).
            if self.executables.is_none() {
                let _ = self.device.device_wait_idle();
            }
            self.device.destroy_command_pool(self.command_pool, None);
            self.device.destroy_device(None);
            if let Some((loader, m)) = self.debug.take() {
                loader.destroy_debug_utils_messenger(m, None);
            }
            self.instance.destroy_instance(None);
        }
    }
}
