//! Specialisation of the path tracer to one pipeline's `override` constants on the host, before
//! the driver sees it: the constants substituted (naga's `process_overrides`, what wgpu would
//! do), then every branch whose condition they decide removed with the functions only it
//! called (`prune_constant_branches`, then naga's `compact`).
//!
//! Why: a driver compiles the SPIR-V it is given whole before its own dead-code elimination.
//! Mesa's software Vulkan (lavapipe) inlines every call of the megakernel into one NIR function
//! first, so a pipeline's compile time grows with the code every scene's features can reach,
//! not with what this scene's features do reach. The images are unchanged: what is removed is
//! what the constants made unreachable.

use naga::valid::{Capabilities, ModuleInfo, ValidationFlags, Validator};
use naga::{Block, Expression, Function, Literal, Module, Statement};

/// A parsed and validated module, specialised per pipeline by `specialise`.
pub struct ParsedModule {
    pub module: Module,
    pub info: ModuleInfo,
}

/// Parses and validates WGSL `source` (errors rendered against it).
pub fn parse(source: &str) -> Result<ParsedModule, String> {
    let module = naga::front::wgsl::parse_str(source).map_err(|e| e.emit_to_string(source))?;
    let info = Validator::new(ValidationFlags::all(), Capabilities::default()).validate(&module).map_err(|e| e.emit_to_string(source))?;
    Ok(ParsedModule { module, info })
}

/// `parsed` with `constants` substituted for its overrides, reduced to the entry point
/// `entry` (a compute shader) and what it can reach under those constants.
pub fn specialise(parsed: &ParsedModule, entry: &str, constants: &[(&str, f64)]) -> Result<Module, String> {
    let mut map = naga::back::PipelineConstants::default();
    for (name, value) in constants {
        map.insert((*name).to_string(), *value);
    }
    let (specialised, _) = naga::back::pipeline_constants::process_overrides(&parsed.module, &parsed.info, Some((naga::ShaderStage::Compute, entry)), &map)
        .map_err(|e| format!("specialisation with {constants:?} failed: {e}"))?;
    let mut module = specialised.into_owned();
    let Module { functions, entry_points, constants, global_expressions, .. } = &mut module;
    for (_, function) in functions.iter_mut() {
        prune_function(function, constants, global_expressions);
    }
    for entry in entry_points.iter_mut() {
        prune_function(&mut entry.function, constants, global_expressions);
    }
    naga::compact::compact(&mut module, naga::compact::KeepUnused::No);
    Ok(module)
}

/// A scalar the constants decide.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Value {
    Bool(bool),
    U32(u32),
    I32(i32),
    F32(f32),
}

/// What the pruning knows: the module's constants, and the values the constants give the
/// compiler's temporaries (the unnamed local variables naga's front end makes for the
/// short-circuit `a && b` and `a || b`: `var t; if (a) { t = b; } else { t = false; }`) at the
/// current statement.
struct Known<'a> {
    function: &'a Function,
    constants: &'a naga::Arena<naga::Constant>,
    global_expressions: &'a naga::Arena<Expression>,
    temporaries: std::collections::HashMap<naga::Handle<naga::LocalVariable>, Value>,
}

impl Known<'_> {
    /// The value of expression `h` where the constants decide it, else `None`.
    fn eval(&self, h: naga::Handle<Expression>) -> Option<Value> {
        self.eval_in(&self.function.expressions, h, 0)
    }

    fn eval_in(&self, arena: &naga::Arena<Expression>, h: naga::Handle<Expression>, depth: u32) -> Option<Value> {
        use naga::{BinaryOperator as B, UnaryOperator as U};
        if depth > 32 {
            return None;
        }
        let sub = |e| self.eval_in(arena, e, depth + 1);
        match &arena[h] {
            Expression::Literal(l) => match *l {
                Literal::Bool(b) => Some(Value::Bool(b)),
                Literal::U32(x) => Some(Value::U32(x)),
                Literal::I32(x) => Some(Value::I32(x)),
                Literal::F32(x) => Some(Value::F32(x)),
                _ => None,
            },
            Expression::Constant(c) => self.eval_in(self.global_expressions, self.constants[*c].init, depth + 1),
            Expression::Load { pointer } if std::ptr::eq(arena, &self.function.expressions) => match arena[*pointer] {
                Expression::LocalVariable(v) => self.temporaries.get(&v).copied(),
                _ => None,
            },
            Expression::Unary { op, expr } => match (op, sub(*expr)?) {
                (U::LogicalNot, Value::Bool(b)) => Some(Value::Bool(!b)),
                (U::BitwiseNot, Value::U32(x)) => Some(Value::U32(!x)),
                (U::BitwiseNot, Value::I32(x)) => Some(Value::I32(!x)),
                _ => None,
            },
            Expression::Binary { op, left, right } => {
                let (l, r) = (sub(*left), sub(*right));
                // Either side decides a logical operator alone.
                match (op, l, r) {
                    (B::LogicalAnd, Some(Value::Bool(false)), _) | (B::LogicalAnd, _, Some(Value::Bool(false))) => return Some(Value::Bool(false)),
                    (B::LogicalOr, Some(Value::Bool(true)), _) | (B::LogicalOr, _, Some(Value::Bool(true))) => return Some(Value::Bool(true)),
                    _ => {}
                }
                binary(*op, l?, r?)
            }
            Expression::As { expr, kind, convert: Some(4) } => match (kind, sub(*expr)?) {
                (naga::ScalarKind::Uint, Value::U32(x)) => Some(Value::U32(x)),
                (naga::ScalarKind::Uint, Value::I32(x)) => Some(Value::U32(x as u32)),
                (naga::ScalarKind::Uint, Value::Bool(b)) => Some(Value::U32(b as u32)),
                (naga::ScalarKind::Sint, Value::I32(x)) => Some(Value::I32(x)),
                (naga::ScalarKind::Sint, Value::U32(x)) => Some(Value::I32(x as i32)),
                (naga::ScalarKind::Sint, Value::Bool(b)) => Some(Value::I32(b as i32)),
                (naga::ScalarKind::Bool, Value::Bool(b)) => Some(Value::Bool(b)),
                _ => None,
            },
            _ => None,
        }
    }

    /// The local variable a pointer expression names where it is one of the compiler's
    /// temporaries (unnamed, without initialiser).
    fn temporary(&self, pointer: naga::Handle<Expression>) -> Option<naga::Handle<naga::LocalVariable>> {
        match self.function.expressions[pointer] {
            Expression::LocalVariable(v) => {
                let var = &self.function.local_variables[v];
                (var.name.is_none() && var.init.is_none()).then_some(v)
            }
            _ => None,
        }
    }
}

/// Whether `block` always ends its enclosing block's run: its last statement returns, discards,
/// breaks or continues, or is a block or an `if` whose every way does.
fn diverges(block: &Block) -> bool {
    match block.last() {
        Some(Statement::Return { .. } | Statement::Kill | Statement::Break | Statement::Continue) => true,
        Some(Statement::Block(b)) => diverges(b),
        Some(Statement::If { accept, reject, .. }) => diverges(accept) && diverges(reject),
        _ => false,
    }
}

/// `l op r` as WGSL computes it, where both are known; `None` for what is not needed here
/// (division, floats but comparisons).
fn binary(op: naga::BinaryOperator, l: Value, r: Value) -> Option<Value> {
    use naga::BinaryOperator as B;
    use Value::*;
    Some(match (op, l, r) {
        (B::Equal, a, b) => Bool(a == b),
        (B::NotEqual, a, b) => Bool(a != b),
        (B::LogicalAnd, Bool(a), Bool(b)) => Bool(a && b),
        (B::LogicalOr, Bool(a), Bool(b)) => Bool(a || b),
        (B::Less, U32(a), U32(b)) => Bool(a < b),
        (B::LessEqual, U32(a), U32(b)) => Bool(a <= b),
        (B::Greater, U32(a), U32(b)) => Bool(a > b),
        (B::GreaterEqual, U32(a), U32(b)) => Bool(a >= b),
        (B::Less, I32(a), I32(b)) => Bool(a < b),
        (B::LessEqual, I32(a), I32(b)) => Bool(a <= b),
        (B::Greater, I32(a), I32(b)) => Bool(a > b),
        (B::GreaterEqual, I32(a), I32(b)) => Bool(a >= b),
        (B::Less, F32(a), F32(b)) => Bool(a < b),
        (B::LessEqual, F32(a), F32(b)) => Bool(a <= b),
        (B::Greater, F32(a), F32(b)) => Bool(a > b),
        (B::GreaterEqual, F32(a), F32(b)) => Bool(a >= b),
        (B::And, U32(a), U32(b)) => U32(a & b),
        (B::InclusiveOr, U32(a), U32(b)) => U32(a | b),
        (B::ExclusiveOr, U32(a), U32(b)) => U32(a ^ b),
        (B::And, Bool(a), Bool(b)) => Bool(a & b),
        (B::InclusiveOr, Bool(a), Bool(b)) => Bool(a | b),
        (B::ShiftLeft, U32(a), U32(b)) if b < 32 => U32(a << b),
        (B::ShiftRight, U32(a), U32(b)) if b < 32 => U32(a >> b),
        (B::Add, U32(a), U32(b)) => U32(a.wrapping_add(b)),
        (B::Subtract, U32(a), U32(b)) => U32(a.wrapping_sub(b)),
        (B::Multiply, U32(a), U32(b)) => U32(a.wrapping_mul(b)),
        (B::Add, I32(a), I32(b)) => I32(a.wrapping_add(b)),
        (B::Subtract, I32(a), I32(b)) => I32(a.wrapping_sub(b)),
        _ => return None,
    })
}

/// Removes from `function` the branches its constant conditions never take. Its named
/// expressions (`let` names, for debugging only) are dropped, so that compaction keeps only
/// what the remaining statements use.
fn prune_function(function: &mut Function, constants: &naga::Arena<naga::Constant>, global_expressions: &naga::Arena<Expression>) {
    let mut body = std::mem::take(&mut function.body);
    let mut known = Known { function, constants, global_expressions, temporaries: Default::default() };
    prune_block(&mut known, &mut body);
    function.body = body;
    function.named_expressions.clear();
}

/// `block` with every `if` whose condition the constants decide replaced by the branch it
/// takes, recursively, in the order the statements run (so that a temporary's value is the one
/// its last store gave it).
fn prune_block(known: &mut Known, block: &mut Block) {
    let mut pruned = Block::with_capacity(block.len());
    for (mut statement, span) in std::mem::take(block).span_into_iter() {
        match &mut statement {
            Statement::If { condition, accept, reject } => {
                if let Some(Value::Bool(taken)) = known.eval(*condition) {
                    let mut branch = std::mem::take(if taken { accept } else { reject });
                    prune_block(known, &mut branch);
                    let diverges = diverges(&branch);
                    if !branch.is_empty() {
                        pruned.push(Statement::Block(branch), span);
                    }
                    if diverges {
                        // The branch returns (or leaves the loop): what follows never runs,
                        // the early-return pattern `if (!HAS_X || ...) { return ...; } ...`.
                        break;
                    }
                    continue;
                }
                let before = known.temporaries.clone();
                prune_block(known, accept);
                known.temporaries = before.clone();
                prune_block(known, reject);
                // Either branch may have run: nothing is known of what they stored.
                known.temporaries.clear();
            }
            Statement::Store { pointer, value } => {
                if let Some(v) = known.temporary(*pointer) {
                    match known.eval(*value) {
                        Some(x) => known.temporaries.insert(v, x),
                        None => known.temporaries.remove(&v),
                    };
                }
            }
            Statement::Block(b) => prune_block(known, b),
            Statement::Switch { cases, .. } => {
                for case in cases {
                    known.temporaries.clear();
                    prune_block(known, &mut case.body);
                }
                known.temporaries.clear();
            }
            Statement::Loop { body, continuing, .. } => {
                // A body runs again after its continuing block: nothing carried in is known.
                known.temporaries.clear();
                prune_block(known, body);
                known.temporaries.clear();
                prune_block(known, continuing);
                known.temporaries.clear();
            }
            _ => {}
        }
        pruned.push(statement, span);
    }
    *block = pruned;
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Three functions, each called only in a branch that overrides decide.
    const SOURCE: &str = "
override USE_B: bool = false;
override N: u32 = 0u;
fn a(x: f32) -> f32 { return x + 1.0; }
fn b(x: f32) -> f32 { return x * 2.0; }
fn c(x: f32) -> f32 { return x - 3.0; }
@group(0) @binding(0) var<storage, read_write> out: array<f32>;
@compute @workgroup_size(1)
fn main() {
    var x = out[0];
    if (USE_B) {
        x = b(x);
    } else {
        x = a(x);
    }
    if (USE_B && N > 2u) {
        let y = c(x);
        x = y;
    }
    out[0] = x;
}
";

    fn functions(m: &Module) -> Vec<String> {
        m.functions.iter().filter_map(|(_, f)| f.name.clone()).collect()
    }

    fn valid(m: &Module) {
        Validator::new(ValidationFlags::all(), Capabilities::default()).validate(m).unwrap();
    }

    #[test]
    fn branches_the_constants_decide_go_with_the_functions_only_they_call() {
        let parsed = parse(SOURCE).unwrap();
        assert_eq!(functions(&parsed.module), ["a", "b", "c"]);
        for (constants, kept) in [
            (vec![("USE_B", 0.0), ("N", 0.0)], vec!["a"]),
            (vec![("USE_B", 1.0), ("N", 3.0)], vec!["b", "c"]),
            (vec![("USE_B", 1.0), ("N", 1.0)], vec!["b"]),
        ] {
            let m = specialise(&parsed, "main", &constants).unwrap();
            assert_eq!(functions(&m), kept, "{constants:?}");
            valid(&m);
        }
    }

    /// The path tracer specialised to the study scene (spheres, planes, Phong) keeps no
    /// triangle traversal and no texture lookup, and far fewer functions than it has.
    #[test]
    fn the_study_scenes_kernel_keeps_only_what_the_scene_reaches() {
        use crate::gpu::{pipeline_constants, AdapterTuning, PipelineKey, SceneFeatures};
        let scene = crate::scene::Scene::load(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes/study.toml")).unwrap();
        let key = PipelineKey::new(crate::method::Preset::Mis.method(), SceneFeatures::of(&scene), scene.default_light_select());
        let mut constants = pipeline_constants(&key);
        constants.extend(AdapterTuning::for_device(wgpu::DeviceType::Cpu).constants());
        let parsed = parse(&crate::shaders::path_tracer_source()).unwrap();
        let m = specialise(&parsed, crate::shaders::PATH_TRACER_ENTRY, &constants).unwrap();
        valid(&m);
        let (all, kept) = (functions(&parsed.module), functions(&m));
        for gone in ["triangles_closest", "bvh_test_leaf", "eval_texture", "triangle_emission", "blend_pick"] {
            assert!(all.iter().any(|f| f == gone) && !kept.iter().any(|f| f == gone), "{gone}");
        }
        assert!(kept.iter().any(|f| f == "eval_sphere_emitter"), "the lights stay");
        assert!(kept.len() * 2 < all.len(), "{} of {} functions kept", kept.len(), all.len());
    }
}
