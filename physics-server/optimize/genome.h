// The genome of a design search: which chain (a letter per position, some
// positions fixed, some a choice, some optional) and which program parameters
// (each a range with a step). Every gene is an integer from 0 to its upper
// bound, so pagmo's GA operators work on it unchanged; decoding turns genes
// into the individual (chain string, parameter values), and the individual's
// key is what the evaluation cache and the history know it by.
#pragma once

#include <cstdint>
#include <exception>
#include <stdexcept>
#include <string>
#include <vector>

namespace chainsim {

// a genome: one integer per gene
using Genes = std::vector<int64_t>;

// the chain part: positions head first; each holds the letters allowed there
// ("T" fixed, "RH" a choice). Positions from min_length on may also be empty
// (the chain is the letters of the non-empty positions, in order).
struct ChainGenome {
  std::vector<std::string> positions;
  int min_length = 0;
};

// one program parameter: value = min + k * step, k = 0 .. count() - 1
struct ParamGene {
  enum class Scope { Central, Module, AllModules, Program };
  // as written: "central.bend_ms", "chain[2].mode", "chain[*].control_ms", "program[fw-sine].amp_cdeg"
  std::string target;
  Scope scope = Scope::Central;
  int module = -1;      // Scope::Module: the chain index
  std::string program;  // Scope::Program: every endpoint (modules, central) whose program has this file name
  std::string name;     // the parameter's name (hal_param)
  int64_t min = 0, max = 0, step = 1;
  std::string where;    // "file:line:column" of its entry in the problem file
  int64_t count() const { return (max - min) / step + 1; }
};

struct GenomeSpec {
  bool has_chain = false;
  ChainGenome chain;
  std::vector<ParamGene> params;

  // the genes: one per chain position with more than one option, then one per parameter
  size_t gene_count() const;
  // largest value of each gene (the smallest is 0)
  std::vector<int64_t> gene_upper() const;
  // a name per gene, for messages: "chain[3]", "central.bend_ms"
  std::vector<std::string> gene_names() const;
  // how many distinct gene vectors there are (saturates at INT64_MAX)
  int64_t gene_space_size() const;
};

// an individual as the simulation sees it
struct Phenotype {
  std::string chain;             // module letters, head first; empty without a chain genome
  std::vector<int64_t> values;   // one per GenomeSpec::params
  bool operator==(const Phenotype& o) const { return chain == o.chain && values == o.values; }
};

struct GenomeError : std::exception {
  explicit GenomeError(std::string w) : what_(std::move(w)) {}
  const char* what() const noexcept override { return what_.c_str(); }
  std::string what_;
};

// genes -> individual; throws GenomeError for a wrong length or a gene out of range
Phenotype decode_genes(const GenomeSpec& spec, const std::vector<int64_t>& genes);
// individual -> the first gene vector that decodes to it (chain letters fill
// the earliest positions that allow them); throws GenomeError if none does
std::vector<int64_t> encode_phenotype(const GenomeSpec& spec, const Phenotype& p);
// "THRH central.bend_ms=1500 chain[*].control_ms=10": the chain, then target=value
std::string phenotype_key(const GenomeSpec& spec, const Phenotype& p);
// the individual of a key (history.csv's genome column); throws GenomeError
// when the key is not one this genome makes
Phenotype phenotype_from_key(const GenomeSpec& spec, const std::string& key);

}  // namespace chainsim
