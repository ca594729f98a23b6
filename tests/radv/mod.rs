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
    // SAFETY: the Vulkan loader library is loaded once here and every object created from it
    // below is destroyed before `entry` goes out of scope.
    let entry_fns = unsafe { ash::Entry::load() }.map_err(|e| format!("no Vulkan loader: {e}"))?;
    let app = vk::ApplicationInfo::default().api_version(vk::API_VERSION_1_3);
    let info = vk::InstanceCreateInfo::default().application_info(&app);
    // SAFETY: `info` and what it points to outlive the call.
    let instance = unsafe { entry_fns.create_instance(&info, None) }
        .map_err(|e| format!("vkCreateInstance: {e}"))?;
    let result = with_instance(&instance, spirv, entry, bindings);
    // SAFETY: every child object of `instance` was destroyed in `with_instance`.
    unsafe { instance.destroy_instance(None) };
    result
}

fn with_instance(
    instance: &ash::Instance,
    spirv: &[u32],
    entry: &str,
    bindings: &[BufferBinding],
) -> Result<Vec<Stats>, String> {
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
    let result = with_device(instance, &device, spirv, entry, bindings);
    // SAFETY: the pipeline and its layouts were destroyed in `with_device`.
    unsafe { device.destroy_device(None) };
    result
}

fn with_device(
    instance: &ash::Instance,
    device: &ash::Device,
    spirv: &[u32],
    entry: &str,
    bindings: &[BufferBinding],
) -> Result<Vec<Stats>, String> {
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
    let stats = pipeline_stats(instance, device, layout, spirv, entry);
    // SAFETY: no pipeline using them is alive any more.
    unsafe {
        device.destroy_pipeline_layout(layout, None);
        for l in set_layouts {
            device.destroy_descriptor_set_layout(l, None);
        }
    }
    stats
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
