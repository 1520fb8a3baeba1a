// disassemble.cpp — a human-readable listing of one material's program
// (pmc info's bytecode dump): opcode names from PMC_OPCODES, operands as
// stack slots or inline constants.
#include <cstring>
#include <sstream>
#include <string>

#include "core/device/pmc_cache_supersample.h"
#include "materials/compiler.h"

namespace pmc {

std::string disassemble(const MaterialProgram& program, const CompiledMaterial& m) {
  static const char* names[] = {
#define PMC_OP_NAME(name, lo, hi, slots) #name,
      PMC_OPCODES(PMC_OP_NAME)
#undef PMC_OP_NAME
  };
  std::ostringstream os;
  uint32_t pc = m.entry;
  const uint32_t end = m.entry + m.code_words;
  while (pc < end) {
    uint32_t h = program.code[pc];
    uint32_t op = pmc_op_code(h);
    os << "  " << pc - m.entry << ": " << (op < PMC_OP_COUNT ? names[op] : "?");
    if (op == PMC_OP_END) {
      os << "\n";
      break;
    }
    os << "." << pmc_op_width(h) << " ";
    if (op == PMC_OP_OUTPUT)
      os << "param[" << pmc_op_imm(h) << "]";
    else
      os << "s" << program.code[pc + 1];
    if (op == PMC_OP_CACHE_LOOKUP) {
      const uint32_t word = program.code[pc + 2];
      os << " node " << (pmc_op_imm(h) & 0x3fffu) << " enc " << (pmc_op_imm(h) >> 14) << " key "
         << ((word & PMC_CACHE_KEY_POSITION) ? "position" : "uv");
      if (pmc_cache_samples_of(word) > 1u) os << " sub-samples " << pmc_cache_samples_of(word);
      os << " (hit: skip " << (word & ~(PMC_CACHE_KEY_POSITION | PMC_CACHE_SAMPLES_MASK)) << " words)\n";
      pc += 3;
      continue;
    }
    if (pmc_op_imm(h) && op != PMC_OP_OUTPUT) os << " #" << pmc_op_imm(h);
    for (uint32_t k = 0; k < pmc_op_nargs(h); ++k) {
      uint32_t o = program.code[pc + 2 + k];
      uint32_t idx = o & PMC_OPERAND_INDEX_MASK, w = pmc_operand_width(o);
      os << (k ? ", " : " <- ");
      if (o & PMC_OPERAND_CONST) {
        os << "(";
        for (uint32_t j = 0; j < w; ++j) {
          float f;
          std::memcpy(&f, &program.code[idx + j], 4);
          os << (j ? " " : "") << f;
        }
        os << ")";
      } else {
        os << "s" << idx << (w > 1 ? "." + std::to_string(w) : "");
      }
    }
    os << "\n";
    pc += 2 + pmc_op_nargs(h);
  }
  return os.str();
}

}  // namespace pmc
