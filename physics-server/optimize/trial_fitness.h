// How an individual's trials make its fitness (problem key evaluation.fitness).
#pragma once

namespace chainsim {

enum class TrialFitness { Mean, Worst, Quantile };

}  // namespace chainsim
