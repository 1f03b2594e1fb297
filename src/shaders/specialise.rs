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
    let is_true = |function: &Function, condition| constant_bool(function, constants, global_expressions, condition);
    for (_, function) in functions.iter_mut() {
        prune_function(function, &is_true);
    }
    for entry in entry_points.iter_mut() {
        prune_function(&mut entry.function, &is_true);
    }
    naga::compact::compact(&mut module, naga::compact::KeepUnused::No);
    Ok(module)
}

/// The value of `condition` in `function` where it is a constant boolean (a literal, or a
/// constant whose value is one), else `None`.
fn constant_bool(
    function: &Function,
    constants: &naga::Arena<naga::Constant>,
    global_expressions: &naga::Arena<Expression>,
    condition: naga::Handle<Expression>,
) -> Option<bool> {
    let literal = |e: &Expression| match e {
        Expression::Literal(Literal::Bool(b)) => Some(*b),
        _ => None,
    };
    match &function.expressions[condition] {
        Expression::Constant(c) => literal(&global_expressions[constants[*c].init]),
        e => literal(e),
    }
}

/// Removes from `function` the branches its constant conditions never take. Its named
/// expressions (`let` names, for debugging only) are dropped, so that compaction keeps only
/// what the remaining statements use.
fn prune_function(function: &mut Function, is_true: &dyn Fn(&Function, naga::Handle<Expression>) -> Option<bool>) {
    let mut body = std::mem::take(&mut function.body);
    prune_block(function, &mut body, is_true);
    function.body = body;
    function.named_expressions.clear();
}

/// `block` with every `if` whose condition is a constant replaced by the branch it takes,
/// recursively.
fn prune_block(function: &Function, block: &mut Block, is_true: &dyn Fn(&Function, naga::Handle<Expression>) -> Option<bool>) {
    let mut pruned = Block::with_capacity(block.len());
    for (mut statement, span) in std::mem::take(block).span_into_iter() {
        match &mut statement {
            Statement::If { condition, accept, reject } => {
                if let Some(taken) = is_true(function, *condition) {
                    let mut branch = std::mem::take(if taken { accept } else { reject });
                    prune_block(function, &mut branch, is_true);
                    if !branch.is_empty() {
                        pruned.push(Statement::Block(branch), span);
                    }
                    continue;
                }
                prune_block(function, accept, is_true);
                prune_block(function, reject, is_true);
            }
            Statement::Block(b) => prune_block(function, b, is_true),
            Statement::Switch { cases, .. } => {
                for case in cases {
                    prune_block(function, &mut case.body, is_true);
                }
            }
            Statement::Loop { body, continuing, .. } => {
                prune_block(function, body, is_true);
                prune_block(function, continuing, is_true);
            }
            _ => {}
        }
        pruned.push(statement, span);
    }
    *block = pruned;
}
