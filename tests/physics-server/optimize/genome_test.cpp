// Genome: genes <-> individuals, keys, bounds.
#include <gtest/gtest.h>

#include "optimize/genome.h"

using namespace chainsim;

namespace {

GenomeSpec chain_genome(std::vector<std::string> pos, int min_length) {
  GenomeSpec g;
  g.has_chain = true;
  g.chain.positions = std::move(pos);
  g.chain.min_length = min_length;
  return g;
}

ParamGene param(const std::string& target, int64_t min, int64_t max, int64_t step) {
  ParamGene p;
  p.target = target;
  p.name = target.substr(target.rfind('.') + 1);
  p.min = min;
  p.max = max;
  p.step = step;
  return p;
}

}  // namespace

TEST(Genome, FixedPositionsHaveNoGeneAndChoicesOneEach) {
  const GenomeSpec g = chain_genome({"T", "RH", "RH", "RH"}, 4);
  EXPECT_EQ(g.gene_count(), 3u);
  EXPECT_EQ(g.gene_upper(), (std::vector<int64_t>{1, 1, 1}));
  EXPECT_EQ(g.gene_names(), (std::vector<std::string>{"chain[1]", "chain[2]", "chain[3]"}));
  EXPECT_EQ(g.gene_space_size(), 8);
  EXPECT_EQ(decode_genes(g, {0, 1, 0}).chain, "TRHR");
  EXPECT_EQ(decode_genes(g, {1, 1, 1}).chain, "THHH");
}

TEST(Genome, OptionalPositionsCanBeEmptyAndAreSkipped) {
  const GenomeSpec g = chain_genome({"T", "RH", "RH", "RH"}, 2);
  // positions 2 and 3 get a third option: empty
  EXPECT_EQ(g.gene_upper(), (std::vector<int64_t>{1, 2, 2}));
  EXPECT_EQ(decode_genes(g, {1, 2, 2}).chain, "TH");
  EXPECT_EQ(decode_genes(g, {0, 2, 1}).chain, "TRH");  // an empty middle position is skipped
  EXPECT_EQ(decode_genes(g, {0, 1, 2}).chain, "TRH");
}

TEST(Genome, ParamsDecodeToMinPlusStepsAndKeysNameThem) {
  GenomeSpec g;
  g.params = {param("central.amplitude_cdeg", 1000, 9000, 100), param("central.phase_mrad", 0, 3000, 20)};
  EXPECT_EQ(g.gene_upper(), (std::vector<int64_t>{80, 150}));
  const Phenotype p = decode_genes(g, {61, 68});
  EXPECT_EQ(p.values, (std::vector<int64_t>{7100, 1360}));
  EXPECT_EQ(phenotype_key(g, p), "central.amplitude_cdeg=7100 central.phase_mrad=1360");
}

TEST(Genome, EncodeIsTheInverseOfDecode) {
  GenomeSpec g = chain_genome({"T", "RH", "RH-", "RHP"}, 2);
  g.chain.positions[2] = "RH";
  g.params = {param("central.bend_ms", 1500, 8000, 500)};
  const auto up = g.gene_upper();
  // every gene vector: decode, encode, decode gives the same individual
  std::vector<int64_t> genes(up.size(), 0);
  int n = 0;
  for (;;) {
    const Phenotype p = decode_genes(g, genes);
    EXPECT_EQ(decode_genes(g, encode_phenotype(g, p)), p) << phenotype_key(g, p);
    ++n;
    size_t k = genes.size();
    while (k > 0 && genes[k - 1] == up[k - 1]) genes[--k] = 0;
    if (k == 0) break;
    ++genes[k - 1];
  }
  EXPECT_EQ(n, g.gene_space_size());
  EXPECT_EQ(encode_phenotype(g, {"THRP", {2000}}), (std::vector<int64_t>{1, 0, 2, 1}));
}

TEST(Genome, WrongGenesAndImpossibleIndividualsAreErrors) {
  const GenomeSpec g = chain_genome({"T", "RH"}, 2);
  EXPECT_THROW(decode_genes(g, {0, 0}), GenomeError);   // one gene expected
  EXPECT_THROW(decode_genes(g, {2}), GenomeError);      // out of range
  EXPECT_THROW(decode_genes(g, {-1}), GenomeError);
  EXPECT_THROW(encode_phenotype(g, {"TS", {}}), GenomeError);
  EXPECT_THROW(encode_phenotype(g, {"T", {}}), GenomeError);  // too short
  GenomeSpec p;
  p.params = {param("central.x", 0, 10, 5)};
  EXPECT_THROW(encode_phenotype(p, {"", {3}}), GenomeError);  // not on a step
  try {
    decode_genes(g, {7});
    FAIL();
  } catch (const GenomeError& e) {
    EXPECT_STREQ(e.what(), "gene chain[1] = 7 is out of range [0, 1]");
  }
}
