//! Register statistics of a compute kernel as Mesa's RADV compiles it, without an AMD GPU:
//! with `VK_ICD_FILENAMES` at the radeon ICD and `RADV_FORCE_FAMILY` (navi21, gfx1100,
//! vega10 …) RADV runs on a null device and still compiles real machine code; the
//! `VK_KHR_pipeline_executable_properties` statistics then give VGPRs, SGPRs, spills and
//! the waves per SIMD the kernel allows. Shared by `tests/gpu_registers.rs` and
//! `examples/kernel_registers.rs`.

#![allow(dead_code)]

use ash::vk;
use refract::gpu::kernels::BufferBinding;
use std::collections::BTreeMap;
use std::ffi::CStr;

/// The radeon ICD that mesa-vulkan-drivers installs.
pub const RADEON_ICD: &str = "/usr/share/vulkan/icd.d/radeon_icd.x86_64.json";

/// One executable's statistics by name ("VGPRs", "Spilled VGPRs", "Subgroups per SIMD", …).
pub type Stats = BTreeMap<String, u64>;

/// Compile `spirv` (entry point `entry`, buffer `bindings`) on the first Vulkan device the
/// loader offers and return the statistics of its executables.
pub fn compile_stats(
    spirv: &[u32],
    entry: &str,
    bindings: &[BufferBinding],
) -> Result<Vec<Stats>, String> {
    on_device(bindings, |instance, device, layout| {
        pipeline_stats(instance, device, layout, spirv, entry)
    })
}

/// Compile `spirv` with a `VkPipelineCache` created from `data` (None: empty) on the first
/// Vulkan device the loader offers: (the pipeline creation's wall time, the cache's data
/// afterwards). What wgpu's `PipelineCache` hands the Vulkan driver.
pub fn compile_time_with_cache(
    spirv: &[u32],
    entry: &str,
    bindings: &[BufferBinding],
    data: Option<&[u8]>,
) -> Result<(std::time::Duration, Vec<u8>), String> {
    on_device(bindings, |_, device, layout| {
        cached_compile(device, layout, spirv, entry, data)
    })
}

/// The device function of [`on_device`]: an instance, a device, and a pipeline layout of
/// the bindings.
type DeviceFn<'a, T> =
    &'a mut dyn FnMut(&ash::Instance, &ash::Device, vk::PipelineLayout) -> Result<T, String>;

/// Run `f` on the first Vulkan device with a pipeline layout of `bindings`.
fn on_device<T>(
    bindings: &[BufferBinding],
    mut f: impl FnMut(&ash::Instance, &ash::Device, vk::PipelineLayout) -> Result<T, String>,
) -> Result<T, String> {
    // SAFETY: the Vulkan loader library is loaded once here and every object created from it
    // below is destroyed before `entry` goes out of scope.
    let entry_fns = unsafe { ash::Entry::load() }.map_err(|e| format!("no Vulkan loader: {e}"))?;
    let app = vk::ApplicationInfo::default().api_version(vk::API_VERSION_1_3);
    let info = vk::InstanceCreateInfo::default().application_info(&app);
    // SAFETY: `info` and what it points to outlive the call.
    let instance = unsafe { entry_fns.create_instance(&info, None) }
        .map_err(|e| format!("vkCreateInstance: {e}"))?;
    let result = with_instance(&instance, bindings, &mut f);
    // SAFETY: every child object of `instance` was destroyed in `with_instance`.
    unsafe { instance.destroy_instance(None) };
    result
}

fn with_instance<T>(
    instance: &ash::Instance,
    bindings: &[BufferBinding],
    f: DeviceFn<'_, T>,
) -> Result<T, String> {
    // SAFETY: a valid instance.
    let pdevs = unsafe { instance.enumerate_physical_devices() }
        .map_err(|e| format!("enumerate devices: {e}"))?;
    let pdev = *pdevs.first().ok_or("no Vulkan device")?;
    let ext = [ash::khr::pipeline_executable_properties::NAME.as_ptr()];
    let mut feat = vk::PhysicalDevicePipelineExecutablePropertiesFeaturesKHR::default()
        .pipeline_executable_info(true);
    let prio = [1.0f32];
    let queue = [vk::DeviceQueueCreateInfo::default()
        .queue_family_index(0)
        .queue_priorities(&prio)];
    let dinfo = vk::DeviceCreateInfo::default()
        .queue_create_infos(&queue)
        .enabled_extension_names(&ext)
        .push_next(&mut feat);
    // SAFETY: `pdev` came from this instance; `dinfo` outlives the call.
    let device = unsafe { instance.create_device(pdev, &dinfo, None) }
        .map_err(|e| format!("vkCreateDevice (pipeline executable properties): {e}"))?;
    let result = with_device(instance, &device, bindings, f);
    // SAFETY: the pipeline and its layouts were destroyed in `with_device`.
    unsafe { device.destroy_device(None) };
    result
}

fn with_device<T>(
    instance: &ash::Instance,
    device: &ash::Device,
    bindings: &[BufferBinding],
    f: DeviceFn<'_, T>,
) -> Result<T, String> {
    let groups = bindings.iter().map(|b| b.group + 1).max().unwrap_or(0);
    let mut set_layouts = Vec::new();
    for g in 0..groups {
        let lb: Vec<vk::DescriptorSetLayoutBinding> = bindings
            .iter()
            .filter(|b| b.group == g)
            .map(|b| {
                vk::DescriptorSetLayoutBinding::default()
                    .binding(b.binding)
                    .descriptor_type(if b.uniform {
                        vk::DescriptorType::UNIFORM_BUFFER
                    } else {
                        vk::DescriptorType::STORAGE_BUFFER
                    })
                    .descriptor_count(1)
                    .stage_flags(vk::ShaderStageFlags::COMPUTE)
            })
            .collect();
        let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&lb);
        // SAFETY: valid device and create info.
        let l = unsafe { device.create_descriptor_set_layout(&info, None) }
            .map_err(|e| format!("descriptor set layout: {e}"))?;
        set_layouts.push(l);
    }
    let pl_info = vk::PipelineLayoutCreateInfo::default().set_layouts(&set_layouts);
    // SAFETY: the set layouts are alive.
    let layout = unsafe { device.create_pipeline_layout(&pl_info, None) }
        .map_err(|e| format!("pipeline layout: {e}"))?;
    let stats = f(instance, device, layout);
    // SAFETY: no pipeline using them is alive any more.
    unsafe {
        device.destroy_pipeline_layout(layout, None);
        for l in set_layouts {
            device.destroy_descriptor_set_layout(l, None);
        }
    }
    stats
}

/// Create the pipeline of `spirv` through a pipeline cache made from `data`, timed.
fn cached_compile(
    device: &ash::Device,
    layout: vk::PipelineLayout,
    spirv: &[u32],
    entry: &str,
    data: Option<&[u8]>,
) -> Result<(std::time::Duration, Vec<u8>), String> {
    let cinfo = vk::PipelineCacheCreateInfo::default().initial_data(data.unwrap_or(&[]));
    // SAFETY: valid device; `data` is what `get_pipeline_cache_data` returned on this driver
    // (and drivers check its header anyway).
    let cache = unsafe { device.create_pipeline_cache(&cinfo, None) }
        .map_err(|e| format!("pipeline cache: {e}"))?;
    let sm_info = vk::ShaderModuleCreateInfo::default().code(spirv);
    // SAFETY: `spirv` is a whole SPIR-V module (naga's output).
    let module = unsafe { device.create_shader_module(&sm_info, None) }
        .map_err(|e| format!("shader module: {e}"))?;
    let name = std::ffi::CString::new(entry).map_err(|e| e.to_string())?;
    let stage = vk::PipelineShaderStageCreateInfo::default()
        .stage(vk::ShaderStageFlags::COMPUTE)
        .module(module)
        .name(&name);
    let info = [vk::ComputePipelineCreateInfo::default()
        .stage(stage)
        .layout(layout)];
    let start = std::time::Instant::now();
    // SAFETY: cache, module and layout are alive; one create info, one pipeline out.
    let created = unsafe { device.create_compute_pipelines(cache, &info, None) };
    let took = start.elapsed();
    // SAFETY: the cache is alive and not used by another thread.
    let out = unsafe { device.get_pipeline_cache_data(cache) };
    // SAFETY: nothing uses the module or the cache any more; the pipeline is not in use.
    unsafe {
        device.destroy_shader_module(module, None);
        if let Ok(p) = &created {
            device.destroy_pipeline(p[0], None);
        }
        device.destroy_pipeline_cache(cache, None);
    }
    created.map_err(|(_, e)| format!("compute pipeline: {e}"))?;
    Ok((took, out.map_err(|e| format!("pipeline cache data: {e}"))?))
}

fn pipeline_stats(
    instance: &ash::Instance,
    device: &ash::Device,
    layout: vk::PipelineLayout,
    spirv: &[u32],
    entry: &str,
) -> Result<Vec<Stats>, String> {
    let sm_info = vk::ShaderModuleCreateInfo::default().code(spirv);
    // SAFETY: `spirv` is a whole SPIR-V module (naga's output).
    let module = unsafe { device.create_shader_module(&sm_info, None) }
        .map_err(|e| format!("shader module: {e}"))?;
    let name = std::ffi::CString::new(entry).map_err(|e| e.to_string())?;
    let stage = vk::PipelineShaderStageCreateInfo::default()
        .stage(vk::ShaderStageFlags::COMPUTE)
        .module(module)
        .name(&name);
    let info = [vk::ComputePipelineCreateInfo::default()
        .stage(stage)
        .layout(layout)
        .flags(vk::PipelineCreateFlags::CAPTURE_STATISTICS_KHR)];
    // SAFETY: module and layout are alive; one create info, one pipeline out.
    let created =
        unsafe { device.create_compute_pipelines(vk::PipelineCache::null(), &info, None) };
    // SAFETY: the module is no longer needed once the pipeline exists (or failed).
    unsafe { device.destroy_shader_module(module, None) };
    let pipeline = created.map_err(|(_, e)| format!("compute pipeline: {e}"))?[0];
    let ext = ash::khr::pipeline_executable_properties::Device::new(instance, device);
    let result = read_stats(&ext, pipeline);
    // SAFETY: the pipeline was created above and is not in use.
    unsafe { device.destroy_pipeline(pipeline, None) };
    result
}

fn read_stats(
    ext: &ash::khr::pipeline_executable_properties::Device,
    pipeline: vk::Pipeline,
) -> Result<Vec<Stats>, String> {
    let pinfo = vk::PipelineInfoKHR::default().pipeline(pipeline);
    // SAFETY: the pipeline was created with CAPTURE_STATISTICS.
    let execs = unsafe { ext.get_pipeline_executable_properties(&pinfo) }
        .map_err(|e| format!("executable properties: {e}"))?;
    let mut out = Vec::new();
    for i in 0..execs.len() as u32 {
        let einfo = vk::PipelineExecutableInfoKHR::default()
            .pipeline(pipeline)
            .executable_index(i);
        // SAFETY: `i` is below the executable count just read.
        let stats = unsafe { ext.get_pipeline_executable_statistics(&einfo) }
            .map_err(|e| format!("executable statistics: {e}"))?;
        let mut m = Stats::new();
        for s in &stats {
            let name = CStr::from_bytes_until_nul(bytemuck_chars(&s.name))
                .map(|c| c.to_string_lossy().into_owned())
                .unwrap_or_default();
            // SAFETY: the union member read is the one `format` names.
            let v = unsafe {
                match s.format {
                    vk::PipelineExecutableStatisticFormatKHR::BOOL32 => u64::from(s.value.b32),
                    vk::PipelineExecutableStatisticFormatKHR::INT64 => s.value.i64.max(0) as u64,
                    vk::PipelineExecutableStatisticFormatKHR::UINT64 => s.value.u64,
                    _ => s.value.f64.max(0.0) as u64,
                }
            };
            m.insert(name, v);
        }
        out.push(m);
    }
    Ok(out)
}

/// The bytes of a C string array.
fn bytemuck_chars(c: &[std::ffi::c_char]) -> &[u8] {
    // SAFETY: c_char is i8 or u8, both one byte with no invalid bit patterns.
    unsafe { std::slice::from_raw_parts(c.as_ptr().cast::<u8>(), c.len()) }
}
