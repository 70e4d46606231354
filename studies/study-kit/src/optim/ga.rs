//! A binary genetic algorithm: chromosomes of up to 32 bits, uniform crossover, independent
//! mutation of every allele, binary tournament selection, one elite kept, and a stop when a
//! fraction of the bit positions is unanimous over the population (or after a number of
//! generations).
//!
//! Reproducible: all random numbers come from one `ChaCha8Rng` seeded by [`Ga::seed`] and are
//! drawn sequentially; the fitness of a generation is evaluated in parallel (rayon) afterwards,
//! so the result does not depend on the number of threads.

use rand::{Rng, SeedableRng};
use rayon::prelude::*;

/// GA settings (seed 001 Table 4's values are the defaults where it gives them).
#[derive(Clone, Debug)]
pub struct Ga {
    /// Population size.
    pub population: usize,
    /// Most generations.
    pub generations: usize,
    /// Seed.
    pub seed: u64,
    /// Crossover probability per bit (uniform).
    pub crossover: f64,
    /// Mutation probability per bit.
    pub mutation: f64,
    /// Stop when this fraction of the bit positions is unanimous.
    pub convergence: f64,
}

impl Default for Ga {
    fn default() -> Self {
        Ga { population: 20, generations: 40, seed: 1, crossover: 0.5, mutation: 0.01, convergence: 0.99 }
    }
}

/// The outcome of a run.
#[derive(Clone, Debug, PartialEq)]
pub struct GaRun {
    /// The best chromosome.
    pub best: u32,
    /// Its fitness (the smallest seen).
    pub fitness: f64,
    /// Generations run.
    pub generations: usize,
    /// Fraction of unanimous bits at the end.
    pub converged: f64,
    /// Fitness evaluations.
    pub evaluations: usize,
    /// Best fitness per generation.
    pub history: Vec<f64>,
}

impl Ga {
    /// Minimise `fitness` over chromosomes of `bits` bits (1..=32).
    pub fn minimise<E: Send>(&self, bits: u32, fitness: impl Fn(u32) -> Result<f64, E> + Sync) -> Result<GaRun, E> {
        assert!((1..=32).contains(&bits), "a chromosome has 1 to 32 bits");
        let mask = if bits == 32 { u32::MAX } else { (1u32 << bits) - 1 };
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(self.seed);
        let mut pop: Vec<u32> = (0..self.population).map(|_| rng.random::<u32>() & mask).collect();
        let mut fit: Vec<f64> = pop.par_iter().map(|g| fitness(*g)).collect::<Result<_, _>>()?;
        let mut evaluations = pop.len();
        let mut history = Vec::new();
        let unanimous = |pop: &[u32]| {
            let same = (0..bits).filter(|b| {
                let ones = pop.iter().filter(|g| (*g >> b) & 1 == 1).count();
                ones == 0 || ones == pop.len()
            });
            same.count() as f64 / f64::from(bits)
        };
        let mut generation = 0;
        loop {
            let best = (0..pop.len()).min_by(|a, b| fit[*a].total_cmp(&fit[*b])).unwrap_or(0);
            history.push(fit[best]);
            if unanimous(&pop) >= self.convergence || generation >= self.generations {
                return Ok(GaRun {
                    best: pop[best],
                    fitness: fit[best],
                    generations: generation,
                    converged: unanimous(&pop),
                    evaluations,
                    history,
                });
            }
            let mut next = vec![pop[best]];
            while next.len() < pop.len() {
                let mut pick = || {
                    let (a, b) = (rng.random_range(0..pop.len()), rng.random_range(0..pop.len()));
                    if fit[a] <= fit[b] { pop[a] } else { pop[b] }
                };
                let (p1, p2) = (pick(), pick());
                let mut child = 0u32;
                for b in 0..bits {
                    let from = if rng.random::<f64>() < self.crossover { p1 } else { p2 };
                    let mut bit = (from >> b) & 1;
                    if rng.random::<f64>() < self.mutation {
                        bit ^= 1;
                    }
                    child |= bit << b;
                }
                next.push(child);
            }
            let new_fit: Vec<f64> = next[1..].par_iter().map(|g| fitness(*g)).collect::<Result<_, _>>()?;
            evaluations += new_fit.len();
            fit = std::iter::once(fit[best]).chain(new_fit).collect();
            pop = next;
            generation += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The GA finds the minimum of a separable function of a 16-bit chromosome (two 8-bit
    /// integers), and the same seed gives the same run.
    #[test]
    fn finds_the_minimum_and_is_reproducible() {
        let f = |g: u32| -> Result<f64, ()> {
            let (a, b) = (f64::from(g & 0xFF), f64::from(g >> 8));
            Ok((a - 77.0).powi(2) + (b - 200.0).powi(2))
        };
        let ga = Ga { population: 40, generations: 200, ..Ga::default() };
        let r = ga.minimise(16, f).unwrap();
        assert!(r.fitness <= 2.0, "{r:?}");
        assert_eq!(ga.minimise(16, f).unwrap(), r);
        assert!(r.history.windows(2).all(|w| w[1] <= w[0]), "the elite keeps the best");
        let other = Ga { seed: 2, ..ga.clone() }.minimise(16, f).unwrap();
        assert_ne!(other.history, r.history);
    }
}
