//! OpenGL, for the compilers of Mesa's OpenGL-only drivers (`shadelab isa`'s nouveau and r600
//! routes, and the OpenGL ES routes of the phone and board GPUs: panfrost, lima, v3d, vc4):
//! the only code that touches EGL (khronos-egl, loading libEGL.so.1 at run time) and OpenGL
//! (glow). A [`GlContext`] is a debug OpenGL 4.3 core context, or the newest OpenGL ES context
//! the driver offers ([`GlApi`]), on an EGL surfaceless display; [`GlContext::compile`]
//! compiles and links one program and returns the KHR_debug messages the driver sent
//! meanwhile, where Mesa's drivers put their compiler statistics (shader-db lines). Nothing is
//! drawn: programs are compiled and linked, never used. [`glsl`] turns our SPIR-V into the
//! GLSL (or GLSL ES) these contexts compile.
pub mod glsl;

use std::sync::{Arc, Mutex};

use glow::HasContext;
use khronos_egl as egl;

use crate::error::{Error, Result};

/// EGL_PLATFORM_SURFACELESS_MESA (EGL_MESA_platform_surfaceless).
const PLATFORM_SURFACELESS_MESA: egl::Enum = 0x31DD;

/// A shader stage of a GL program.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GlStage {
    Vertex,
    Fragment,
    Compute,
}

impl GlStage {
    fn gl(self) -> u32 {
        match self {
            GlStage::Vertex => glow::VERTEX_SHADER,
            GlStage::Fragment => glow::FRAGMENT_SHADER,
            GlStage::Compute => glow::COMPUTE_SHADER,
        }
    }
}

/// Which OpenGL a [`GlContext`] speaks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GlApi {
    /// OpenGL 4.3 core (GLSL 4.30).
    Core43,
    /// The newest of OpenGL ES 3.2, 3.1, 3.0 and 2.0 the driver creates.
    Es,
}

/// The OpenGL ES versions [`GlApi::Es`] tries, newest first.
const ES_VERSIONS: [(i32, i32); 4] = [(3, 2), (3, 1), (3, 0), (2, 0)];

/// What the context says it is.
#[derive(Debug, Clone)]
pub struct GlInfo {
    /// GL_RENDERER ("NV162", "AMD CAYMAN (DRM 2.50.0 / ...)", or "llvmpipe (...)" when the
    /// driver fell back to software).
    pub renderer: String,
    pub vendor: String,
    /// GL_VERSION ("4.3 (Core Profile) Mesa 22.3.6", "OpenGL ES 3.1 Mesa 25.0.7").
    pub version: String,
    /// The OpenGL ES version of an ES context (`None` for OpenGL 4.3 core).
    pub es: Option<(u32, u32)>,
    /// The bits of precision of a fragment shader's `mediump float` (GL's shader precision
    /// format): 10 where the driver computes mediump in float16, 23 where in float32.
    pub mediump_bits: i32,
}

/// A current OpenGL context on an EGL surfaceless display, with KHR_debug messages collected.
/// Owns its EGL display and context; dropping it releases them. One per process (the child
/// of `shadelab isa`): the context is current on the thread that made it.
pub struct GlContext {
    egl: egl::DynamicInstance<egl::EGL1_5>,
    display: egl::Display,
    context: egl::Context,
    gl: glow::Context,
    messages: Arc<Mutex<Vec<String>>>,
    info: GlInfo,
}

fn egl_err(call: &str, e: impl std::fmt::Display) -> Error {
    Error::Device(format!(
        "EGL: {call} failed: {e} (the OpenGL route needs Debian's libegl1 and libegl-mesa0, and \
         a driver the environment selects: docs/isa.md)"
    ))
}

impl GlContext {
    /// Loads libEGL.so.1, opens the surfaceless display (the driver Mesa's loader picks, e.g.
    /// through MESA_LOADER_DRIVER_OVERRIDE), and makes a debug OpenGL 4.3 core context
    /// current without a surface.
    pub fn surfaceless() -> Result<Self> {
        Self::surfaceless_api(GlApi::Core43)
    }

    /// [`GlContext::surfaceless`] for `api`: OpenGL 4.3 core, or the newest OpenGL ES version
    /// the driver creates.
    pub fn surfaceless_api(api: GlApi) -> Result<Self> {
        // SAFETY: libEGL.so.1 is the system's EGL (libglvnd), which implements the EGL API
        // khronos-egl binds.
        let egl = unsafe { egl::DynamicInstance::<egl::EGL1_5>::load_required() }
            .map_err(|e| egl_err("loading libEGL.so.1", e))?;
        // SAFETY: the surfaceless platform takes no native display (EGL_DEFAULT_DISPLAY).
        let display = unsafe {
            egl.get_platform_display(
                PLATFORM_SURFACELESS_MESA,
                egl::DEFAULT_DISPLAY,
                &[egl::ATTRIB_NONE],
            )
        }
        .map_err(|e| egl_err("eglGetPlatformDisplay(surfaceless)", e))?;
        egl.initialize(display)
            .map_err(|e| egl_err("eglInitialize", e))?;
        let (context, es) = match api {
            GlApi::Core43 => (core_context(&egl, display)?, None),
            GlApi::Es => es_context(&egl, display)?,
        };
        egl.make_current(display, None, None, Some(context))
            .map_err(|e| egl_err("eglMakeCurrent(surfaceless)", e))?;
        // SAFETY: the context is current on this thread; the loader returns entry points of
        // that context's driver (null for those it lacks, which glow leaves unset).
        let mut gl = unsafe {
            glow::Context::from_loader_function(|name| {
                egl.get_proc_address(name)
                    .map_or(std::ptr::null(), |f| f as *const std::ffi::c_void)
            })
        };
        let messages: Arc<Mutex<Vec<String>>> = Arc::default();
        let sink = messages.clone();
        // SAFETY: the context is current; the callback only copies the message text.
        let info = unsafe {
            gl.enable(glow::DEBUG_OUTPUT);
            gl.enable(glow::DEBUG_OUTPUT_SYNCHRONOUS);
            gl.debug_message_control(glow::DONT_CARE, glow::DONT_CARE, glow::DONT_CARE, &[], true);
            gl.debug_message_callback(move |_source, _type, _id, _severity, text| {
                if let Ok(mut m) = sink.lock() {
                    m.push(text.to_string());
                }
            });
            GlInfo {
                renderer: gl.get_parameter_string(glow::RENDERER),
                vendor: gl.get_parameter_string(glow::VENDOR),
                version: gl.get_parameter_string(glow::VERSION),
                es,
                mediump_bits: gl
                    .get_shader_precision_format(glow::FRAGMENT_SHADER, glow::MEDIUM_FLOAT)
                    .map_or(0, |f| f.precision),
            }
        };
        Ok(GlContext {
            egl,
            display,
            context,
            gl,
            messages,
            info,
        })
    }

    pub fn info(&self) -> &GlInfo {
        &self.info
    }

    /// Compiles `stages` (GLSL sources) and links them into one program, then deletes it;
    /// returns the KHR_debug messages the driver sent meanwhile. A compile or link error is
    /// an [`Error::Shader`] with the driver's log, naming `label`.
    pub fn compile(&self, label: &str, stages: &[(GlStage, &str)]) -> Result<Vec<String>> {
        let gl = &self.gl;
        self.messages
            .lock()
            .map_err(|_| Error::Internal("GL message lock poisoned".into()))?
            .clear();
        // SAFETY: the context is current on this thread (made so in `surfaceless`, and
        // `GlContext` is not Send); every object made here is deleted before returning.
        let linked = unsafe {
            let program = gl
                .create_program()
                .map_err(|e| Error::Shader(format!("{label}: glCreateProgram: {e}")))?;
            let mut shaders = Vec::new();
            let mut failure = None;
            for (stage, source) in stages {
                let shader = gl
                    .create_shader(stage.gl())
                    .map_err(|e| Error::Shader(format!("{label}: glCreateShader: {e}")))?;
                gl.shader_source(shader, source);
                gl.compile_shader(shader);
                if !gl.get_shader_compile_status(shader) && failure.is_none() {
                    failure = Some(format!(
                        "{label}: the {stage:?} shader does not compile: {}",
                        gl.get_shader_info_log(shader)
                    ));
                }
                gl.attach_shader(program, shader);
                shaders.push(shader);
            }
            if failure.is_none() {
                gl.link_program(program);
                if !gl.get_program_link_status(program) {
                    failure = Some(format!(
                        "{label}: the program does not link: {}",
                        gl.get_program_info_log(program)
                    ));
                }
            }
            for s in shaders {
                gl.detach_shader(program, s);
                gl.delete_shader(s);
            }
            gl.delete_program(program);
            failure
        };
        if let Some(why) = linked {
            return Err(Error::Shader(why));
        }
        let messages = self
            .messages
            .lock()
            .map_err(|_| Error::Internal("GL message lock poisoned".into()))?;
        Ok(messages.clone())
    }
}

/// A debug OpenGL 4.3 core context.
fn core_context(
    egl: &egl::DynamicInstance<egl::EGL1_5>,
    display: egl::Display,
) -> Result<egl::Context> {
    egl.bind_api(egl::OPENGL_API)
        .map_err(|e| egl_err("eglBindAPI(OpenGL)", e))?;
    // SAFETY: EGL_NO_CONFIG_KHR (null): Mesa's displays have EGL_KHR_no_config_context.
    let no_config = unsafe { egl::Config::from_ptr(std::ptr::null_mut()) };
    let attrs = [
        egl::CONTEXT_MAJOR_VERSION,
        4,
        egl::CONTEXT_MINOR_VERSION,
        3,
        egl::CONTEXT_OPENGL_PROFILE_MASK,
        egl::CONTEXT_OPENGL_CORE_PROFILE_BIT,
        egl::CONTEXT_OPENGL_DEBUG,
        egl::TRUE as egl::Int,
        egl::NONE,
    ];
    egl.create_context(display, no_config, None, &attrs)
        .map_err(|e| egl_err("eglCreateContext(OpenGL 4.3 core, debug)", e))
}

/// A debug OpenGL ES context of the newest version of [`ES_VERSIONS`] the driver creates.
fn es_context(
    egl: &egl::DynamicInstance<egl::EGL1_5>,
    display: egl::Display,
) -> Result<(egl::Context, Option<(u32, u32)>)> {
    egl.bind_api(egl::OPENGL_ES_API)
        .map_err(|e| egl_err("eglBindAPI(OpenGL ES)", e))?;
    // SAFETY: as in `core_context`.
    let no_config = unsafe { egl::Config::from_ptr(std::ptr::null_mut()) };
    let mut last = None;
    for (major, minor) in ES_VERSIONS {
        let attrs = [
            egl::CONTEXT_MAJOR_VERSION,
            major,
            egl::CONTEXT_MINOR_VERSION,
            minor,
            egl::CONTEXT_OPENGL_DEBUG,
            egl::TRUE as egl::Int,
            egl::NONE,
        ];
        match egl.create_context(display, no_config, None, &attrs) {
            Ok(c) => return Ok((c, Some((major as u32, minor as u32)))),
            Err(e) => last = Some(e),
        }
    }
    Err(egl_err(
        "eglCreateContext(OpenGL ES 3.2, 3.1, 3.0 or 2.0, debug)",
        last.map_or_else(|| "no version tried".to_string(), |e| e.to_string()),
    ))
}

impl Drop for GlContext {
    fn drop(&mut self) {
        // Errors on the way out are of no use: the process ends right after.
        let _ = self.egl.make_current(self.display, None, None, None);
        let _ = self.egl.destroy_context(self.display, self.context);
        let _ = self.egl.terminate(self.display);
    }
}
