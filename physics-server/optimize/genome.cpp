#include "optimize/genome.h"

#include <stdexcept>

#include <limits>

namespace chainsim {

namespace {

constexpr char kEmpty = '-';

// the options of chain position i: its letters, plus "empty" past min_length
std::string position_options(const ChainGenome& c, size_t i) {
  std::string o = c.positions[i];
  if (static_cast<int>(i) >= c.min_length) o += kEmpty;
  return o;
}

}  // namespace

size_t GenomeSpec::gene_count() const { return gene_upper().size(); }

std::vector<int64_t> GenomeSpec::gene_upper() const {
  std::vector<int64_t> up;
  if (has_chain)
    for (size_t i = 0; i < chain.positions.size(); ++i) {
      const size_t n = position_options(chain, i).size();
      if (n > 1) up.push_back(static_cast<int64_t>(n) - 1);
    }
  for (const auto& p : params) up.push_back(p.count() - 1);
  return up;
}

std::vector<std::string> GenomeSpec::gene_names() const {
  std::vector<std::string> names;
  if (has_chain)
    for (size_t i = 0; i < chain.positions.size(); ++i)
      if (position_options(chain, i).size() > 1) names.push_back("chain[" + std::to_string(i) + "]");
  for (const auto& p : params) names.push_back(p.target);
  return names;
}

int64_t GenomeSpec::gene_space_size() const {
  int64_t n = 1;
  for (int64_t u : gene_upper()) {
    if (n > std::numeric_limits<int64_t>::max() / (u + 1)) return std::numeric_limits<int64_t>::max();
    n *= u + 1;
  }
  return n;
}

Phenotype decode_genes(const GenomeSpec& spec, const std::vector<int64_t>& genes) {
  const std::vector<int64_t> up = spec.gene_upper();
  if (genes.size() != up.size())
    throw GenomeError("a genome of " + std::to_string(genes.size()) + " genes, expected " +
                      std::to_string(up.size()));
  const std::vector<std::string> names = spec.gene_names();
  for (size_t g = 0; g < genes.size(); ++g)
    if (genes[g] < 0 || genes[g] > up[g])
      throw GenomeError("gene " + names[g] + " = " + std::to_string(genes[g]) + " is out of range [0, " +
                        std::to_string(up[g]) + "]");
  Phenotype p;
  size_t g = 0;
  if (spec.has_chain)
    for (size_t i = 0; i < spec.chain.positions.size(); ++i) {
      const std::string o = position_options(spec.chain, i);
      const char letter = o.size() > 1 ? o[static_cast<size_t>(genes[g++])] : o[0];
      if (letter != kEmpty) p.chain += letter;
    }
  for (const auto& pg : spec.params) p.values.push_back(pg.min + genes[g++] * pg.step);
  return p;
}

std::vector<int64_t> encode_phenotype(const GenomeSpec& spec, const Phenotype& p) {
  std::vector<int64_t> genes;
  if (spec.has_chain) {
    const auto& pos = spec.chain.positions;
    const size_t n = pos.size(), m = p.chain.size();
    // can[i][j]: positions i.. can spell letters j..
    std::vector<std::vector<char>> can(n + 1, std::vector<char>(m + 1, 0));
    can[n][m] = 1;
    for (size_t i = n; i-- > 0;)
      for (size_t j = 0; j <= m; ++j) {
        const std::string o = position_options(spec.chain, i);
        can[i][j] = (j < m && o.find(p.chain[j]) != std::string::npos && can[i + 1][j + 1]) ||
                    (o.find(kEmpty) != std::string::npos && can[i + 1][j]);
      }
    if (!can[0][0]) throw GenomeError("chain '" + p.chain + "' cannot be made by the chain genome");
    size_t j = 0;
    for (size_t i = 0; i < n; ++i) {
      const std::string o = position_options(spec.chain, i);
      size_t pick;
      if (j < m && o.find(p.chain[j]) != std::string::npos && can[i + 1][j + 1]) {
        pick = o.find(p.chain[j]);
        ++j;
      } else {
        pick = o.find(kEmpty);
      }
      if (o.size() > 1) genes.push_back(static_cast<int64_t>(pick));
    }
  } else if (!p.chain.empty()) {
    throw GenomeError("the genome has no chain, the individual has '" + p.chain + "'");
  }
  if (p.values.size() != spec.params.size())
    throw GenomeError(std::to_string(p.values.size()) + " parameter values, expected " +
                      std::to_string(spec.params.size()));
  for (size_t k = 0; k < spec.params.size(); ++k) {
    const ParamGene& pg = spec.params[k];
    const int64_t v = p.values[k];
    if (v < pg.min || v > pg.max || (v - pg.min) % pg.step != 0)
      throw GenomeError(pg.target + " = " + std::to_string(v) + " is not one of " + std::to_string(pg.min) +
                        ".." + std::to_string(pg.max) + " in steps of " + std::to_string(pg.step));
    genes.push_back((v - pg.min) / pg.step);
  }
  return genes;
}

std::string phenotype_key(const GenomeSpec& spec, const Phenotype& p) {
  std::string k = p.chain;
  for (size_t i = 0; i < spec.params.size() && i < p.values.size(); ++i) {
    if (!k.empty()) k += ' ';
    k += spec.params[i].target + "=" + std::to_string(p.values[i]);
  }
  return k;
}

}  // namespace chainsim

namespace chainsim {

Phenotype phenotype_from_key(const GenomeSpec& spec, const std::string& key) {
  std::vector<std::string> words;
  size_t a = 0;
  while (a < key.size()) {
    const size_t b = key.find(' ', a);
    words.push_back(key.substr(a, b == std::string::npos ? std::string::npos : b - a));
    if (b == std::string::npos) break;
    a = b + 1;
  }
  Phenotype p;
  size_t w = 0;
  if (spec.has_chain) {
    if (words.empty()) throw GenomeError("'" + key + "': no chain");
    p.chain = words[w++];
  }
  if (words.size() - w != spec.params.size())
    throw GenomeError("'" + key + "': " + std::to_string(words.size() - w) + " parameters, the genome has " +
                      std::to_string(spec.params.size()));
  for (const ParamGene& g : spec.params) {
    const std::string& word = words[w++];
    const std::string head = g.target + "=";
    if (word.compare(0, head.size(), head) != 0) throw GenomeError("'" + key + "': expected " + head + "...");
    try {
      size_t used = 0;
      p.values.push_back(std::stoll(word.substr(head.size()), &used));
      if (used != word.size() - head.size()) throw std::invalid_argument("trailing");
    } catch (const std::exception&) {
      throw GenomeError("'" + key + "': '" + word + "' is not " + head + "<integer>");
    }
  }
  if (phenotype_key(spec, p) != key) throw GenomeError("'" + key + "' is not a key of this genome");
  return p;
}

}  // namespace chainsim
