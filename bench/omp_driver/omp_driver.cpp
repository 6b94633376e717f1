// Command-line driver for bench/compare_omp_sklearn.py: runs our Batch-OMP (Rubinstein, Zibulevsky
// & Elad 2008) on a dictionary and signals written by the Python script, so that both coders see
// exactly the same data. Not a Google Benchmark file on purpose: every bench/bench_*.cpp is linked
// with benchmark_main, and this program needs its own main() and file I/O.
//
//   omp_driver DICTIONARY SIGNALS n K P S REPEATS CODES_OUT
//
// DICTIONARY (n × K) and SIGNALS (n × P) are raw little-endian float64 in column-major order
// (numpy: M.T.tofile()). Runs batchOMP with S atoms per signal REPEATS times on one OpenMP thread,
// writes the codes of the last run as dense column-major K × P float64 to CODES_OUT, and prints
// one JSON line with the wall time of each run and the best. Timed: batchOMP itself, i.e. Dᵀx
// (inside batchOMP), the OMP iterations and assembling the sparse code matrix. Not timed: DᵀD,
// which batchOMP takes precomputed (once per dictionary), and the file I/O.
#include <pcl_patchdict/coding/sparse_coding.h>

#include <Eigen/Core>

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

// The files are read by reinterpreting their bytes, which is right only on little-endian hosts.
static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "raw float64 files are little-endian");
static_assert(sizeof(double) == 8, "float64 expected");

Eigen::MatrixXd readRaw(const std::string& path, Eigen::Index rows, Eigen::Index cols)
{
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw std::runtime_error("cannot open " + path);
  Eigen::MatrixXd m(rows, cols);
  const auto bytes = static_cast<std::streamsize>(sizeof(double) * static_cast<std::size_t>(m.size()));
  in.read(reinterpret_cast<char*>(m.data()), bytes);
  if (in.gcount() != bytes || in.peek() != std::char_traits<char>::eof())
    throw std::runtime_error(path + " does not hold " + std::to_string(rows) + " x " + std::to_string(cols) +
                             " float64 values");
  return m;
}

void writeRaw(const std::string& path, const Eigen::MatrixXd& m)
{
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(m.data()),
            static_cast<std::streamsize>(sizeof(double) * static_cast<std::size_t>(m.size())));
  if (!out)
    throw std::runtime_error("cannot write " + path);
}

Eigen::Index positive(const char* text, const char* what)
{
  char* end = nullptr;
  const long long value = std::strtoll(text, &end, 10);
  if (end == text || *end != '\0' || value < 1)
    throw std::runtime_error(std::string(what) + " must be a positive integer, got '" + text + "'");
  return static_cast<Eigen::Index>(value);
}

}  // namespace

int main(int argc, char** argv)
{
  if (argc != 9) {
    std::fprintf(stderr, "usage: %s DICTIONARY SIGNALS n K P S REPEATS CODES_OUT\n", argv[0]);
    return 2;
  }
  try {
    // Per-core throughput is what we compare: sklearn's orthogonal_mp_gram codes one signal at a
    // time in one thread as well.
    omp_set_num_threads(1);
    const Eigen::Index n = positive(argv[3], "n"), atoms = positive(argv[4], "K"), count = positive(argv[5], "P");
    const int sparsity = static_cast<int>(positive(argv[6], "S"));
    const int repeats = static_cast<int>(positive(argv[7], "REPEATS"));
    const Eigen::MatrixXd dictionary = readRaw(argv[1], n, atoms);
    const Eigen::MatrixXd signals = readRaw(argv[2], n, count);
    const Eigen::MatrixXd gram = dictionary.transpose() * dictionary;
    const pcl::patchdict::SparseCodingParameters parameters{sparsity, 0.0};

    std::vector<double> seconds;
    pcl::patchdict::SparseCodes codes;
    for (int r = 0; r < repeats; ++r) {
      const auto start = std::chrono::steady_clock::now();
      codes = pcl::patchdict::batchOMP(dictionary, gram, signals, parameters);
      seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    }
    writeRaw(argv[8], Eigen::MatrixXd(codes));

    std::printf("{\"best_seconds\": %.9g, \"seconds\": [", *std::min_element(seconds.begin(), seconds.end()));
    for (std::size_t i = 0; i < seconds.size(); ++i)
      std::printf("%s%.9g", i ? ", " : "", seconds[i]);
    std::printf("], \"threads\": %d}\n", omp_get_max_threads());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "omp_driver: %s\n", e.what());
    return 1;
  }
}
