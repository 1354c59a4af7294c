//! Held against the shaders: the passes that run every frame never branch on a setting alone.
//! lavapipe (Mesa 22.3), the driver of the tests and CI, specialises a shader on the push
//! constants and uniforms that a branch or a loop bound depends on alone, keeps no cache of its
//! specialisations and, unless its first try shrank the shader too little, compiles it again at
//! every dispatch: the G-buffer warp took about 380 ms of LLVM a frame at 640x360 before it read its settings
//! through `unspecialised` (shaders/include/warp.wgsl). This finds such branches in the warps, the
//! hole fill and the flow's loops; other passes run once or gain too little for the driver to keep
//! specialising.

#[allow(dead_code)]
#[path = "../build_support/wgsl.rs"]
mod wgsl;

use std::collections::HashSet;
use std::path::Path;

use naga::{AddressSpace, Block, Expression, Function, Handle, Module, Statement};

/// Where a value comes from, as a driver sees it when the pass is dispatched. Ordered, so that
/// an expression takes the latest of its operands'.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
enum Source {
    Constant,
    /// Constants and at least one push constant or uniform: known at every dispatch.
    Settings,
    /// Anything read per invocation: images, storage, built-ins, results of calls.
    Varying,
}

/// A function of the module: a helper or an entry point.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
enum Place {
    Helper(Handle<Function>),
    Entry(usize),
}

struct Analysis<'a> {
    module: &'a Module,
    /// Every call: the caller, the callee, the arguments in the caller's arena.
    calls: Vec<(Place, Handle<Function>, Vec<Handle<Expression>>)>,
    /// (place, expression) pairs being resolved: a cycle is a value that changes per iteration.
    visiting: HashSet<(Place, Handle<Expression>)>,
}

fn function(module: &Module, place: Place) -> &Function {
    match place {
        Place::Helper(handle) => &module.functions[handle],
        Place::Entry(index) => &module.entry_points[index].function,
    }
}

/// Every statement of `block` and of the blocks inside it.
fn walk<'b>(block: &'b Block, visit: &mut impl FnMut(&'b Statement)) {
    for statement in block.iter() {
        visit(statement);
        match statement {
            Statement::Block(inner) => walk(inner, visit),
            Statement::If { accept, reject, .. } => {
                walk(accept, visit);
                walk(reject, visit);
            }
            Statement::Switch { cases, .. } => cases.iter().for_each(|c| walk(&c.body, visit)),
            Statement::Loop {
                body, continuing, ..
            } => {
                walk(body, visit);
                walk(continuing, visit);
            }
            _ => {}
        }
    }
}

fn places(module: &Module) -> impl Iterator<Item = Place> + '_ {
    let helpers = module
        .functions
        .iter()
        .map(|(handle, _)| Place::Helper(handle));
    helpers.chain((0..module.entry_points.len()).map(Place::Entry))
}

/// The variable a pointer expression starts from.
fn root(function: &Function, mut pointer: Handle<Expression>) -> Handle<Expression> {
    loop {
        match function.expressions[pointer] {
            Expression::Access { base, .. } | Expression::AccessIndex { base, .. } => {
                pointer = base
            }
            _ => return pointer,
        }
    }
}

impl<'a> Analysis<'a> {
    fn new(module: &'a Module) -> Self {
        let mut calls = Vec::new();
        for place in places(module) {
            walk(&function(module, place).body, &mut |statement| {
                if let Statement::Call {
                    function: callee,
                    arguments,
                    ..
                } = statement
                {
                    calls.push((place, *callee, arguments.clone()));
                }
            });
        }
        Self {
            module,
            calls,
            visiting: HashSet::new(),
        }
    }

    fn latest(&mut self, place: Place, operands: &[Handle<Expression>]) -> Source {
        let mut source = Source::Constant;
        for &operand in operands {
            source = source.max(self.source(place, operand));
        }
        source
    }

    fn source(&mut self, place: Place, expression: Handle<Expression>) -> Source {
        if !self.visiting.insert((place, expression)) {
            return Source::Varying;
        }
        let source = self.resolve(place, expression);
        self.visiting.remove(&(place, expression));
        source
    }

    fn resolve(&mut self, place: Place, expression: Handle<Expression>) -> Source {
        let f = function(self.module, place);
        match f.expressions[expression] {
            Expression::Literal(_) | Expression::Constant(_) | Expression::ZeroValue(_) => {
                Source::Constant
            }
            Expression::Compose { ref components, .. } => self.latest(place, components),
            Expression::Access { base, index } => self.latest(place, &[base, index]),
            Expression::AccessIndex { base, .. } => self.source(place, base),
            Expression::Splat { value, .. } => self.source(place, value),
            Expression::Swizzle { vector, .. } => self.source(place, vector),
            Expression::Unary { expr, .. } => self.source(place, expr),
            Expression::Binary { left, right, .. } => self.latest(place, &[left, right]),
            Expression::Select {
                condition,
                accept,
                reject,
            } => self.latest(place, &[condition, accept, reject]),
            Expression::Relational { argument, .. } => self.source(place, argument),
            Expression::As { expr, .. } => self.source(place, expr),
            Expression::Math {
                arg,
                arg1,
                arg2,
                arg3,
                ..
            } => {
                let operands: Vec<_> = [Some(arg), arg1, arg2, arg3]
                    .into_iter()
                    .flatten()
                    .collect();
                self.latest(place, &operands)
            }
            Expression::Load { pointer } => self.loaded(place, root(f, pointer)),
            Expression::FunctionArgument(index) => self.argument(place, index as usize),
            _ => Source::Varying,
        }
    }

    /// A load through a pointer rooted at `variable`.
    fn loaded(&mut self, place: Place, variable: Handle<Expression>) -> Source {
        let f = function(self.module, place);
        match f.expressions[variable] {
            Expression::GlobalVariable(global) => {
                match self.module.global_variables[global].space {
                    AddressSpace::Immediate | AddressSpace::Uniform => Source::Settings,
                    _ => Source::Varying,
                }
            }
            // A local holds what is stored into it (and its initialiser).
            Expression::LocalVariable(local) => {
                let mut values: Vec<_> = f.local_variables[local].init.into_iter().collect();
                walk(&f.body, &mut |statement| {
                    if let Statement::Store { pointer, value } = *statement {
                        if root(f, pointer) == variable {
                            values.push(value);
                        }
                    }
                });
                self.latest(place, &values)
            }
            _ => Source::Varying,
        }
    }

    /// An argument of a helper: what its callers pass; an entry point's are built-ins.
    fn argument(&mut self, place: Place, index: usize) -> Source {
        let Place::Helper(callee) = place else {
            return Source::Varying;
        };
        let passed: Vec<_> = self
            .calls
            .iter()
            .filter(|(_, called, _)| *called == callee)
            .map(|(caller, _, arguments)| (*caller, arguments[index]))
            .collect();
        let mut source = Source::Constant;
        for (caller, argument) in passed {
            source = source.max(self.source(caller, argument));
        }
        source
    }

    /// Whether `condition`, which ends a loop, compares a local (the loop's counter) with
    /// settings: the driver inlines those to unroll the loop.
    fn bounds_a_loop_by_settings(&mut self, place: Place, condition: Handle<Expression>) -> bool {
        let f = function(self.module, place);
        let mut condition = condition;
        while let Expression::Unary { expr, .. } = f.expressions[condition] {
            condition = expr;
        }
        let Expression::Binary { left, right, .. } = f.expressions[condition] else {
            return false;
        };
        let is_counter = |side: Handle<Expression>| {
            matches!(f.expressions[side], Expression::Load { pointer }
                if matches!(f.expressions[root(f, pointer)], Expression::LocalVariable(_)))
        };
        (is_counter(left) && self.source(place, right) == Source::Settings)
            || (is_counter(right) && self.source(place, left) == Source::Settings)
    }

    /// The branches of the module that depend on settings alone, described.
    fn branches_on_settings(&mut self) -> Vec<String> {
        let mut found = Vec::new();
        for place in places(self.module) {
            let f = function(self.module, place);
            let mut conditions = Vec::new();
            walk(&f.body, &mut |statement| match statement {
                Statement::If { condition, .. } => conditions.push(("if", *condition)),
                Statement::Switch { selector, .. } => conditions.push(("switch", *selector)),
                Statement::Loop { body, break_if, .. } => {
                    conditions.extend(break_if.map(|condition| ("break if", condition)));
                    loop_exits(body, &mut conditions);
                }
                _ => {}
            });
            let name = f.name.clone().unwrap_or_default();
            for (kind, condition) in conditions {
                if self.source(place, condition) == Source::Settings
                    || (kind == "loop exit" && self.bounds_a_loop_by_settings(place, condition))
                {
                    found.push(format!("{kind} in {name}: {:?}", f.expressions[condition]));
                }
            }
        }
        found
    }
}

/// The conditions that end the loop whose body is `body`: `if (c) { break; }` at its top level.
fn loop_exits(body: &Block, conditions: &mut Vec<(&'static str, Handle<Expression>)>) {
    for statement in body.iter() {
        if let Statement::If {
            condition,
            accept,
            reject,
        } = statement
        {
            let breaks = |block: &Block| matches!(block.iter().next(), Some(Statement::Break));
            if breaks(accept) || breaks(reject) {
                conditions.push(("loop exit", *condition));
            }
        }
    }
}

fn module(pass: &str) -> Module {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let source = wgsl::assemble(
        &root.join("shaders").join(format!("{pass}.wgsl")),
        &root.join("shaders/include"),
    )
    .expect("the pass assembles");
    naga::front::wgsl::parse_str(&source.text).expect("the pass parses")
}

#[test]
fn the_warps_the_fill_and_the_flow_never_branch_on_settings_alone() {
    for pass in [
        "warp_gbuffer",
        "warp_occlusion_motion",
        "warp_motion_vector",
        "fill_holes",
        "shadow_mask_finest",
        "shadow_mask_pyramid",
        "shadow_poly",
        "shadow_flow_iterate",
    ] {
        let module = module(pass);
        let found = Analysis::new(&module).branches_on_settings();
        assert!(found.is_empty(), "{pass}: {found:#?}");
    }
}

/// The analysis finds what it is for: the shaders as they were, with a setting in a branch and
/// one as a loop's bound.
#[test]
fn a_branch_or_a_loop_bound_on_settings_alone_is_found() {
    let found = |source: &str| {
        let module = naga::front::wgsl::parse_str(source).expect("the test shader parses");
        Analysis::new(&module).branches_on_settings()
    };
    let shader = |body: &str| {
        format!(
            "struct Params {{ flag: u32, radius: i32 }}
            var<immediate> params: Params;
            @group(0) @binding(0) var image: texture_2d<f32>;
            @group(0) @binding(1) var<storage, read_write> out: array<f32>;
            fn helper(setting: u32, p: vec2u) -> f32 {{
                var sum = 0.0;
                {body}
                return sum;
            }}
            @compute @workgroup_size(8, 8, 1)
            fn main(@builtin(global_invocation_id) id: vec3u) {{
                out[id.x] = helper(params.flag, id.xy);
            }}"
        )
    };
    // A setting passed to a helper, branched on there.
    assert_eq!(found(&shader("if (setting != 0u) { sum = 1.0; }")).len(), 1);
    // A loop bounded by a setting.
    let bounded = "for (var i = -params.radius; i <= params.radius; i++) { sum += f32(i); }";
    assert_eq!(found(&shader(bounded)).len(), 1);
    // Tied to an image's size, neither qualifies; a branch on what is read per pixel never did.
    let tied = "let live = textureDimensions(image).x != 0u;
        if (select(0u, setting, live) != 0u) { sum = 1.0; }
        let r = select(0, params.radius, live);
        for (var i = -r; i <= r; i++) { sum += f32(i); }
        if (textureLoad(image, p, 0).x > 0.5) { sum = 2.0; }";
    assert_eq!(found(&shader(tied)), Vec::<String>::new());
}
