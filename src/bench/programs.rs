//! The programs a bench times: the constant-colour floors, the methods, the control and
//! `auto`, each with the floor it is measured against.
use crate::error::Result;
use crate::gpu::{DrawList, GpuScene, Prepared, Renderer, Shading};
use crate::method::{Geometry, Method};

/// The name of the constant-colour program on geometry `g`.
pub fn floor_name(g: Geometry) -> String {
    match g {
        Geometry::Mesh => "constant".into(),
        Geometry::PnTessellated(level) => format!("constant_pn_tessellated_{level}"),
    }
}

/// What a timed program shades with.
#[derive(Clone, Copy)]
pub(super) enum What<'a> {
    /// The constant colour (a floor).
    Floor,
    Method(&'a Method),
    /// phong_exact's program under another name.
    Control(&'a Method),
    /// `auto`: its groups, each with the method chosen for its triangles.
    Auto(&'a crate::gpu::AutoScene),
}

/// A timed program of a run: what it draws and the floor it is measured against.
pub(super) struct Program<'a> {
    pub name: String,
    pub gpu: &'a GpuScene,
    pub what: What<'a>,
    /// Index of its floor among the programs (the scene's floor, 0, is its own).
    pub floor: usize,
}

impl<'a> Program<'a> {
    /// The draw as timed and counted.
    pub fn list(&self) -> DrawList<'a> {
        match self.what {
            What::Floor => DrawList::whole(self.gpu, Shading::Constant),
            What::Method(m) => DrawList::whole(self.gpu, Shading::Method(m)),
            What::Control(m) => DrawList::whole(self.gpu, Shading::Control(m)),
            What::Auto(a) => a.draw_list(),
        }
    }

    /// The method of the table whose program this is (none for a floor or `auto`).
    pub fn method(&self) -> Option<&'a Method> {
        match self.what {
            What::Method(m) | What::Control(m) => Some(m),
            What::Floor | What::Auto(_) => None,
        }
    }

    /// The image, for its coverage.
    pub fn render(&self, renderer: &Renderer) -> Result<crate::frame::Frame> {
        match self.what {
            What::Floor => Ok(renderer.render(self.gpu, Shading::Constant, false)?.0),
            What::Method(m) => Ok(renderer.render(self.gpu, Shading::Method(m), false)?.0),
            What::Control(m) => Ok(renderer.render(self.gpu, Shading::Control(m), false)?.0),
            What::Auto(a) => renderer.render_auto(a),
        }
    }
}

/// The programs of a run, all timed in the same rounds: the floor of the scene's triangles
/// first, then the floor of every other geometry (measured against the first: the cost of
/// that geometry), the methods (each against the floor of its geometry), the control and
/// `auto` (on the scene's triangles, against the first floor).
pub(super) fn programs<'a>(
    prepared: &'a Prepared,
    methods: &[&'a Method],
    control: Option<&'a Method>,
    autos: &'a [(String, crate::gpu::AutoScene)],
) -> Vec<Program<'a>> {
    let geometries = prepared.geometries();
    let mut out: Vec<Program> = Vec::new();
    for g in &geometries {
        if let Some(gpu) = prepared.for_geometry(*g) {
            out.push(Program {
                name: floor_name(*g),
                gpu,
                what: What::Floor,
                floor: 0,
            });
        }
    }
    let floor_of = |g: Geometry| geometries.iter().position(|x| *x == g).unwrap_or(0);
    for m in methods {
        out.push(Program {
            name: m.name.to_string(),
            gpu: prepared.for_method(m),
            what: What::Method(m),
            floor: floor_of(m.geometry),
        });
    }
    if let Some(m) = control {
        out.push(Program {
            name: Shading::Control(m).name(),
            gpu: prepared.for_method(m),
            what: What::Control(m),
            floor: floor_of(m.geometry),
        });
    }
    for (name, a) in autos {
        out.push(Program {
            name: name.clone(),
            gpu: &a.gpu,
            what: What::Auto(a),
            floor: 0,
        });
    }
    out
}
