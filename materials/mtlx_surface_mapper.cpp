// mtlx_surface_mapper.cpp — a MaterialX document's materials, each a Graph
// whose `surface` is a node pmc's BSDF reads.
//
// The mapper finds the document's materials (surfacematerials, custom nodes
// and nodegraph outputs of type material, else one preview per output) and
// follows each to its surface shader; everything below a shader's inputs is
// the instantiator's (mtlx_instantiator.h), which it calls through its named
// functions and which calls back build_surface() for each surface shader node
// it meets. Surface shaders (standard_surface, UsdPreviewSurface,
// open_pbr_surface, gltf_pbr, disney_principled, surface_unlit) map their
// inputs onto pmc's parameters (node_table.h: surface_params), with the
// shader-specific rules (glTF's alpha mode, UsdPreviewSurface's opacity as
// glass, disney_principled's affine inputs); a shader built of pbrlib
// closures is flattened (closure_flatten.h). A material that cannot be built
// keeps its error in Graph::error; a document none of whose materials can be
// built throws the first.
#include <vector>

#include "core/error.h"
#include "materials/closure_flatten.h"
#include "materials/mtlx_document_xml.h"
#include "materials/mtlx_instantiator.h"
#include "materials/mtlx_matrix.h"
#include "materials/node_table.h"

namespace pmc {
namespace {

class SurfaceMapper {
 public:
  SurfaceMapper(const std::string& path, const MtlxReadOptions& options, pugi::xml_node root)
      : path_(path),
        root_(root),
        inst_(path, options, root,
              [this](const MtlxScope& scope, pugi::xml_node el, Node& node, const std::string& context) {
                build_surface(scope, el, node, context);
              }) {}

  // The materials of `root`, a document MtlxDocument loaded (upgraded, its
  // includes expanded).
  std::vector<Graph> read() {
    std::vector<Graph> out;
    MtlxScope top{root_, 0, nullptr, ""};
    for (pugi::xml_node el : root_.children("surfacematerial")) {
      inst_.begin(el.attribute("name").as_string());
      attempt(out, [&] {
        pugi::xml_node in = el.find_child_by_attribute("input", "name", "surfaceshader");
        if (!in) fail(inst_.where(el), ": surfacematerial has no 'surfaceshader' input");
        inst_.graph().surface = shader_of(top, in, inst_.where(el) + " input 'surfaceshader'");
      });
    }
    // Materials that are not surfacematerial nodes: custom nodes of type
    // material, and nodegraphs whose outputs are materials (named like
    // previews: the nodegraph, or nodegraph/output when it has several).
    for (pugi::xml_node el : root_.children()) {
      if (std::string(el.attribute("type").as_string()) != "material" || mtlx_is_structural(el.name()) ||
          std::string(el.name()) == "surfacematerial" || std::string(el.name()) == "output")
        continue;
      inst_.begin(el.attribute("name").as_string());
      attempt(out, [&] { inst_.graph().surface = material_node_surface(top, el, inst_.where(el)); });
    }
    for (pugi::xml_node ng : root_.children("nodegraph")) {
      if (ng.attribute("nodedef")) continue;  // an implementation of a custom node
      std::vector<pugi::xml_node> materials;
      int outputs = 0;
      for (pugi::xml_node o : ng.children("output")) {
        ++outputs;
        if (std::string(o.attribute("type").as_string()) == "material") materials.push_back(o);
      }
      for (pugi::xml_node o : materials) {
        const std::string ng_name = ng.attribute("name").as_string();
        inst_.begin(outputs == 1 ? ng_name : ng_name + "/" + o.attribute("name").as_string());
        attempt(out, [&] {
          inst_.graph().surface = material_surface(MtlxScope{ng, 0, nullptr, ""}, o, inst_.where(o));
        });
      }
    }
    if (out.empty()) preview_outputs(out);
    if (out.empty()) fail(path_, ": no surfacematerial and no outputs: nothing to render");
    for (const Graph& g : out)
      if (g.error.empty()) return out;
    throw Error(out.front().error);
  }

 private:
  // Builds the current material with `build`; an error makes it a failed
  // material (Graph::error) instead of failing the document.
  template <class F>
  void attempt(std::vector<Graph>& out, F&& build) {
    try {
      build();
      out.push_back(std::move(inst_.graph()));
    } catch (const Error& e) {
      Graph failed;
      failed.material = inst_.graph().material;
      failed.file = path_;
      failed.error = e.what();
      out.push_back(std::move(failed));
    }
  }

  // The shader a surfacematerial (or a surfaceshader output) points at.
  int shader_of(const MtlxScope& scope, pugi::xml_node in, const std::string& context) {
    Input s;
    s.name = "surfaceshader";
    s.type = ValueType::Surface;
    inst_.connect(scope, in, s, context);
    if (!s.linked) fail(context, ": is not connected to a shader");
    const Node& shader = inst_.graph().nodes[size_t(s.node)];
    if (mtlx_is_surface_shader(shader.category)) return s.node;
    if (!inst_.is_closure_node(s.node))
      fail(shader.origin, ": '", shader.category,
           "' is not a supported surface shader (pmc supports standard_surface, UsdPreviewSurface, "
           "open_pbr_surface, gltf_pbr, disney_principled, surface_unlit, and pbrlib closure graphs)");
    const std::string origin = shader.origin;  // flattening adds nodes: `shader` may move
    std::vector<std::string> unmodelled;
    const int flat = flatten_closure_shader(inst_.graph(), s.node, unmodelled);
    if (!unmodelled.empty()) {
      std::string list;
      for (const std::string& u : unmodelled) list += (list.empty() ? "" : "; ") + u;
      warn(origin + ": closure graph flattened onto pmc's BSDF; not modelled: " + list);
    }
    return flat;
  }

  // The surface shader of a material node: a surfacematerial's
  // 'surfaceshader' input, or, for a custom node of type material (a
  // nodedef whose nodegraph outputs a material), the material its
  // implementation graph outputs.
  int material_node_surface(const MtlxScope& scope, pugi::xml_node node, const std::string& context,
                            int depth = 0) {
    if (depth > 16) fail(context, ": materials nested deeper than 16 definitions");
    if (std::string(node.name()) == "surfacematerial") {
      pugi::xml_node in = node.find_child_by_attribute("input", "name", "surfaceshader");
      if (!in) fail(inst_.where(scope, node), ": surfacematerial has no 'surfaceshader' input");
      return shader_of(scope, in, inst_.where(scope, node) + " input 'surfaceshader'");
    }
    const std::string where = inst_.where(scope, node);
    const MtlxScope implementation = inst_.implementation_scope(scope, node, where);
    pugi::xml_node out = implementation.graph.find_child_by_attribute("output", "type", "material");
    if (!out) fail(where, ": its definition's nodegraph outputs no material");
    return material_surface(implementation, out, where, depth + 1);
  }

  // The surface shader behind an element of type material (a nodegraph's or
  // the document's <output>) that names a material node.
  int material_surface(const MtlxScope& scope, pugi::xml_node el, const std::string& context, int depth = 0) {
    if (el.attribute("nodegraph")) {
      pugi::xml_node ng =
          root_.find_child_by_attribute("nodegraph", "name", el.attribute("nodegraph").as_string());
      pugi::xml_node out = ng ? ng.find_child_by_attribute("output", "type", "material") : pugi::xml_node();
      if (!out)
        fail(context, ": nodegraph '", el.attribute("nodegraph").as_string(), "' outputs no material");
      return material_surface(MtlxScope{ng, 0, nullptr, ""}, out, context, depth + 1);
    }
    const std::string nodename = el.attribute("nodename").as_string();
    pugi::xml_node node =
        nodename.empty() ? pugi::xml_node() : MtlxInstantiator::find_node(scope.graph, nodename);
    if (!node) fail(context, ": is not connected to a material node");
    return material_node_surface(scope, node, context, depth);
  }

  // A surface shader node's inputs: its parameters' defaults, then the
  // document's inputs connected, then the shader's own rules.
  void build_surface(const MtlxScope& scope, pugi::xml_node el, Node& node, const std::string& context) {
    std::vector<SurfaceParam> params = surface_params(node.category);
    std::string ignored;
    for (const SurfaceParam& p : params) {
      Input in;
      in.name = p.input;
      in.type = p.type;
      in.value = Value::number(p.type, p.def[0], p.def[1], p.def[2]);
      node.inputs.push_back(in);
    }
    for (pugi::xml_node c : el.children("input")) {
      std::string name = c.attribute("name").as_string();
      Input* in = name.compare(0, 4, "pmc_") == 0 ? nullptr : node.input(name);
      if (!in) {
        if (node.category == "gltf_pbr" && (name == "alpha_mode" || name == "alpha_cutoff")) continue;
        if (node.category == "UsdPreviewSurface" && name == "opacityThreshold") continue;
        ignored += (ignored.empty() ? "" : ", ") + name;
        continue;
      }
      ValueType declared = parse_type(c.attribute("type").as_string());
      if (declared != ValueType::None && declared != in->type &&
          !(declared == ValueType::Float && type_width(in->type) > 1) &&
          !(type_width(declared) == type_width(in->type) && is_numeric(declared)))
        fail(context, ": input '", name, "' must be ", type_name(in->type), ", the document says ",
             type_name(declared), " (type mismatch)");
      if (inst_.stands_for_default(scope, c, context + " input '" + name + "'")) continue;
      inst_.connect(scope, c, *in, context + " input '" + name + "'");
    }
    if (node.category == "gltf_pbr") {  // alpha is the opacity only in alpha_mode MASK (1) or BLEND (2)
      pugi::xml_node mode = el.find_child_by_attribute("input", "name", "alpha_mode");
      bool opaque = !mode || (!mode.attribute("nodename") && mode.attribute("value").as_int() == 0);
      Input* alpha = node.input("alpha");
      if (opaque && (alpha->linked || alpha->value.f[0] != 1.0f)) {
        *alpha = Input::constant("alpha", ValueType::Float, 1.0f);
        ignored += std::string(ignored.empty() ? "" : ", ") + "alpha (alpha_mode OPAQUE)";
      }
      if (mode && !opaque)
        ignored += std::string(ignored.empty() ? "" : ", ") + "alpha_cutoff (pmc cuts at 0.5)";
    }
    // UsdPreviewSurface: with opacityThreshold 0 (its default) an opacity
    // below 1 is glass that refracts by `ior` (its specification), so it
    // becomes transmission 1 - opacity; above 0 it stays a cut-out.
    if (node.category == "UsdPreviewSurface") {
      pugi::xml_node th = el.find_child_by_attribute("input", "name", "opacityThreshold");
      const bool cutout = th && (th.attribute("nodename") || th.attribute("value").as_float() > 0.0f);
      Input* opacity = node.input("opacity");
      if (!cutout && (opacity->linked || opacity->value.f[0] != 1.0f)) {
        Input* trans = node.input("pmc_transmission");
        if (!opacity->linked) {
          *trans = Input::constant("pmc_transmission", ValueType::Float, 1.0f - opacity->value.f[0]);
        } else {
          Node sub;
          sub.category = "subtract";
          sub.type = ValueType::Float;
          sub.origin = context + " input 'opacity' (glass: transmission = 1 - opacity)";
          Input a = *opacity;
          a.name = "in2";
          sub.inputs = {Input::constant("in1", ValueType::Float, 1.0f), a};
          *trans = Input::link("pmc_transmission", ValueType::Float, inst_.graph().add(std::move(sub)));
        }
        *opacity = Input::constant("opacity", ValueType::Float, 1.0f);
      }
    }
    // Parameters that are an affine function of their input (disney_principled).
    for (const SurfaceParam& p : params) {
      if (p.scale == 1.0f && p.offset == 0.0f) continue;
      Input* in = node.input(p.input);
      if (!in->linked) {
        for (float& f : in->value.f) f = f * p.scale + p.offset;
        continue;
      }
      Node mul;
      mul.category = "multiply";
      mul.type = ValueType::Float;
      mul.origin = context + " input '" + p.input + "' (scaled for pmc's BSDF)";
      Input a = *in;
      a.name = "in1";
      mul.inputs = {a, Input::constant("in2", ValueType::Float, p.scale)};
      Node add;
      add.category = "add";
      add.type = ValueType::Float;
      add.origin = mul.origin;
      add.inputs = {Input::link("in1", ValueType::Float, inst_.graph().add(std::move(mul))),
                    Input::constant("in2", ValueType::Float, p.offset)};
      *in = Input::link(p.input, in->type, inst_.graph().add(std::move(add)));
    }
    if (!ignored.empty()) warn(context + ": inputs pmc does not model (ignored): " + ignored);
  }

  // Documents without materials: one preview material per output.
  void preview_outputs(std::vector<Graph>& out) {
    auto add_preview = [&](const MtlxScope& scope, pugi::xml_node output, const std::string& name) {
      inst_.begin(name);
      attempt(out, [&] {
        const std::string origin = path_ + ": output '" + name + "'";
        const std::string type = output.attribute("type").as_string();
        if (type == "surfaceshader") {  // a shader output is a material
          inst_.graph().surface = shader_of(scope, output, origin);
          return;
        }
        if (type == "material") {
          inst_.graph().surface = material_surface(scope, output, origin);
          return;
        }
        Node conv;
        conv.category = "convert";
        conv.type = ValueType::Color3;
        conv.origin = origin;
        Input in;
        in.name = "in";
        in.type = parse_type(type);
        if (is_matrix(in.type)) {  // shown as its first row (mtlx_matrix.h)
          inst_.connect(scope, output, in, conv.origin);
          Matrix m = Matrix::of(inst_.constant_of(in, conv.origin));
          Input row = Input::constant("in", ValueType::Color3, float(m.at(0, 0)), float(m.at(0, 1)),
                                      float(m.at(0, 2)));
          warn(conv.origin + ": a " + type + " output is previewed as its first row (m00, m01, m02)");
          in = row;
        } else {
          if (!is_numeric(in.type))
            fail(conv.origin, ": output type '", type,
                 "' cannot be shown (pmc previews numeric, matrix and surfaceshader outputs)");
          inst_.connect(scope, output, in, conv.origin);
          if (in.linked) {
            const Node& src = inst_.graph().nodes[size_t(in.node)];
            if (!is_numeric(src.type) || is_matrix(src.type))  // a matrix has no lanes to convert
              fail(conv.origin, ": output type '", type, "' but node '", src.name, "' outputs ",
                   type_name(src.type), " (type mismatch)");
            in.type = src.type;
          }
        }
        conv.inputs.push_back(in);
        int c = inst_.graph().add(conv);
        Node surface;
        surface.category = "standard_surface";
        surface.type = ValueType::Surface;
        surface.origin = conv.origin + " (preview surface)";
        for (const SurfaceParam& p : surface_params("standard_surface")) {
          Input si;
          si.name = p.input;
          si.type = p.type;
          si.value = Value::number(p.type, p.def[0], p.def[1], p.def[2]);
          if (si.name == "base_color") si.linked = true, si.node = c;
          if (si.name == "specular") si.value.f[0] = 0.0f;  // a flat preview shows the pattern itself
          surface.inputs.push_back(si);
        }
        inst_.graph().surface = inst_.graph().add(surface);
      });
    };
    for (pugi::xml_node o : root_.children("output"))
      add_preview(MtlxScope{root_, 0, nullptr, ""}, o, o.attribute("name").as_string());
    for (pugi::xml_node ng : root_.children("nodegraph")) {
      if (ng.attribute("nodedef")) continue;  // an implementation of a custom node, not a graph to show
      std::string ng_name = ng.attribute("name").as_string();
      int count = 0;
      for (pugi::xml_node o : ng.children("output")) {
        (void)o;
        ++count;
      }
      for (pugi::xml_node o : ng.children("output")) {
        std::string name = count == 1 ? ng_name : ng_name + "/" + o.attribute("name").as_string();
        add_preview(MtlxScope{ng, 0, nullptr, ""}, o, name);
      }
    }
  }

  std::string path_;
  pugi::xml_node root_;
  MtlxInstantiator inst_;
};

}  // namespace

std::vector<Graph> read_mtlx_graphs(const MtlxDocument& doc) {
  return SurfaceMapper(doc.path(), doc.options(), doc.xml().root).read();
}

}  // namespace pmc
