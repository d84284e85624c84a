// The main() of a fuzz harness built without libFuzzer (gcc, the CI's ASan + UBSan test build):
// runs LLVMFuzzerTestOneInput on every given input file, then on a fixed number of mutants of
// them, taken in turn (byte flips, truncations, insertions, splices) from a seeded generator. Deterministic,
// so a CI failure replays exactly; coverage-guided fuzzing stays with scripts/fuzz.sh (clang).
#include <stdlib.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

using Bytes = std::vector<std::uint8_t>;

struct Options {
  std::size_t runs = 500;  // mutants in all, from the inputs in turn
  std::uint32_t seed = 1;
  std::size_t max_len = 16384;  // as scripts/fuzz.sh's -max_len
  std::vector<std::filesystem::path> inputs;
};

void usage(const char* self) {
  std::cout << "usage: " << self << " [--runs N] [--seed S] [--max-len BYTES] FILE_OR_DIR...\n"
            << "Runs this fuzz harness on every input file (directories: every file in them),\n"
            << "then on N mutants of them in turn (default 500), from seed S (default 1). Exit 0 when no\n"
            << "input crashed it (ASan/UBSan abort otherwise). Built without libFuzzer; for\n"
            << "coverage-guided fuzzing use scripts/fuzz.sh.\n";
}

bool parse(int argc, char** argv, Options& o) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has_value = i + 1 < argc;
    if (a == "-h" || a == "--help") {
      usage(argv[0]);
      std::exit(0);
    } else if (a == "--runs" && has_value) {
      o.runs = std::stoul(argv[++i]);
    } else if (a == "--seed" && has_value) {
      o.seed = static_cast<std::uint32_t>(std::stoul(argv[++i]));
    } else if (a == "--max-len" && has_value) {
      o.max_len = std::stoul(argv[++i]);
    } else if (!a.empty() && a[0] == '-') {
      std::cerr << argv[0] << ": unknown option " << a << "\n";
      return false;
    } else {
      o.inputs.emplace_back(a);
    }
  }
  return !o.inputs.empty();
}

std::vector<std::filesystem::path> inputFiles(const std::vector<std::filesystem::path>& given) {
  std::vector<std::filesystem::path> files;
  for (const auto& p : given) {
    if (!std::filesystem::is_directory(p)) {
      files.push_back(p);
      continue;
    }
    for (const auto& e : std::filesystem::directory_iterator(p))
      if (e.is_regular_file()) files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());  // same order on every machine
  return files;
}

Bytes readFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path.string());
  return Bytes(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// One of a few edits libFuzzer also makes; several per mutant so headers and bodies both change.
void mutate(Bytes& b, const Bytes& other, std::mt19937& rng) {
  const auto pick = [&rng](std::size_t n) { return std::uniform_int_distribution<std::size_t>(0, n)(rng); };
  const int edits = 1 + static_cast<int>(pick(3));
  for (int e = 0; e < edits; ++e) {
    switch (pick(4)) {
      case 0:  // flip a bit
        if (!b.empty()) b[pick(b.size() - 1)] ^= static_cast<std::uint8_t>(1u << pick(7));
        break;
      case 1:  // an extreme byte value
        if (!b.empty()) b[pick(b.size() - 1)] = pick(1) ? 0xFF : 0x00;
        break;
      case 2:  // truncate
        b.resize(pick(b.size()));
        break;
      case 3:  // insert random bytes
        b.insert(b.begin() + static_cast<std::ptrdiff_t>(pick(b.size())), pick(8),
                 static_cast<std::uint8_t>(pick(255)));
        break;
      default:  // splice: the head of this input with the tail of another
        if (!other.empty()) {
          const std::size_t cut = pick(b.size()), from = pick(other.size());
          b.resize(cut);
          b.insert(b.end(), other.begin() + static_cast<std::ptrdiff_t>(from), other.end());
        }
    }
  }
}

// A private $TMPDIR for the harness's temporary files and MAP_COMMAND file_dir (as
// scripts/fuzz.sh gives each harness), removed with everything in it at the end.
class ScratchDir {
 public:
  ScratchDir() {
    const char* tmp = std::getenv("TMPDIR");
    std::string pattern = std::string(tmp ? tmp : "/tmp") + "/socc_fuzz_replay_XXXXXX";
    if (!::mkdtemp(pattern.data())) throw std::runtime_error("mkdtemp failed");
    path_ = pattern;
    ::setenv("TMPDIR", path_.c_str(), 1);
  }
  ~ScratchDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;

 private:
  std::filesystem::path path_;
};

void run(const Bytes& b, std::size_t max_len) {
  LLVMFuzzerTestOneInput(b.data(), std::min(b.size(), max_len));
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  if (!parse(argc, argv, o)) {
    usage(argv[0]);
    return 2;
  }
  try {
    const ScratchDir scratch;
    const auto files = inputFiles(o.inputs);
    std::vector<Bytes> corpus;
    for (const auto& f : files) corpus.push_back(readFile(f));
    if (corpus.empty()) throw std::runtime_error("no input files (a seed corpus is needed)");
    for (const auto& b : corpus) run(b, o.max_len);
    std::mt19937 rng(o.seed);
    for (std::size_t r = 0; r < o.runs; ++r) {
      const std::size_t i = r % corpus.size();
      Bytes b = corpus[i];
      mutate(b, corpus[(i + r / corpus.size() + 1) % corpus.size()], rng);
      run(b, o.max_len);
    }
    std::cout << argv[0] << ": " << corpus.size() << " inputs and "
              << o.runs << " mutants ran without a finding\n";
  } catch (const std::exception& e) {
    std::cerr << argv[0] << ": " << e.what() << "\n";
    return 1;
  }
  return 0;
}
