// emit.h — one node into bytecode instructions, and constant folding.
//
// The Emitter collects one material's instructions and its inline constants
// (placed after END by finish()). emit_node() turns one primitive node into
// instructions, as its node-table entry says (NodeDef::emit): an opcode with
// the operand inputs in table order, or one of the few special emitters
// (convert, extract, swizzle, combine2, image, operand-width opcodes). evaluate_constant()
// runs that same emission through the host interpreter for a node whose
// inputs are all constant: constant folding can never disagree with the
// renderer.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "core/abi/pmc_bytecode.h"
#include "core/error.h"
#include "core/texture.h"
#include "materials/node_graph.h"

namespace pmc {

uint32_t float_bits(float f);

// Appends instructions for one material into a local buffer; constants are
// collected and placed after END by finish(), which patches the operands.
class Emitter {
 public:
  uint32_t constant(const Value& v, int width) {
    width = std::max(1, std::min(4, width));
    std::vector<uint32_t> bits;
    for (int i = 0; i < width; ++i) bits.push_back(float_bits(v.f[size_t(i)]));
    auto it = const_index_.find(bits);
    uint32_t offset;
    if (it != const_index_.end()) {
      offset = it->second;
    } else {
      offset = uint32_t(consts_.size());
      consts_.insert(consts_.end(), bits.begin(), bits.end());
      const_index_[bits] = offset;
    }
    return pmc_operand(1, offset, uint32_t(width));  // patched in finish()
  }
  static uint32_t slot(uint32_t index, int width) {
    return pmc_operand(0, index, uint32_t(std::max(1, width)));
  }

  void instr(int op, int width, uint32_t imm, uint32_t dst, const std::vector<uint32_t>& operands) {
    PMC_CHECK(imm < 65536u && operands.size() < 16, "instruction encoding");
    code_.push_back(pmc_op_header(uint32_t(op), uint32_t(std::max(1, std::min(4, width))),
                                  uint32_t(operands.size()), imm));
    code_.push_back(dst);
    for (uint32_t o : operands) {
      if (o & PMC_OPERAND_CONST) fixups_.push_back(code_.size());
      code_.push_back(o);
    }
    ++instructions_;
  }

  // An instruction whose operand words are raw integers (not patched as constants).
  void instr_raw(int op, int width, uint32_t imm, uint32_t dst, const std::vector<uint32_t>& words) {
    code_.push_back(
        pmc_op_header(uint32_t(op), uint32_t(std::max(1, std::min(4, width))), uint32_t(words.size()), imm));
    code_.push_back(dst);
    code_.insert(code_.end(), words.begin(), words.end());
    ++instructions_;
  }
  size_t size() const { return code_.size(); }
  void patch(size_t at, uint32_t word) { code_[at] = word; }

  // END, then constants; operands become absolute indices from `base`.
  std::vector<uint32_t> finish(uint32_t base) {
    code_.push_back(pmc_op_header(PMC_OP_END, 1, 0, 0));
    code_.push_back(0);
    uint32_t const_base = base + uint32_t(code_.size());
    for (size_t at : fixups_) {
      uint32_t o = code_[at];
      code_[at] = (o & ~PMC_OPERAND_INDEX_MASK) | ((o & PMC_OPERAND_INDEX_MASK) + const_base);
    }
    std::vector<uint32_t> out = code_;
    out.insert(out.end(), consts_.begin(), consts_.end());
    return out;
  }
  uint32_t instructions() const { return instructions_; }

 private:
  std::vector<uint32_t> code_, consts_;
  std::vector<size_t> fixups_;
  std::map<std::vector<uint32_t>, uint32_t> const_index_;
  uint32_t instructions_ = 0;
};

struct EmitContext {
  const Graph& g;
  TexturePool* textures;  // null when folding
  Emitter& em;
  std::function<uint32_t(const Input&)> operand;  // maps an input to an operand word
};

// Emits `n` writing its value to slot `dst`. Returns false if it cannot be
// evaluated without a shading point (only matters when folding).
bool emit_node(EmitContext& cx, const Node& n, uint32_t dst);

// Evaluates a node whose inputs are all constants (constant folding).
// Returns false if the node cannot be folded (geometric, image ...).
bool evaluate_constant(const Graph& g, const Node& n, Value& out);

}  // namespace pmc
