// libFuzzer harness: the F readers. The first byte picks the format (even: .hff, odd: .mtx); the
// rest is the file. Any input must end in a valid FormFactors or a hemirad::Error.
#include "engine/error.hpp"
#include "engine/form_factor_file.hpp"

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size == 0) return 0;
    const std::string name = data[0] % 2 == 0 ? "fuzz.hff" : "fuzz.mtx";
    const std::string bytes(reinterpret_cast<const char*>(data + 1), size - 1);
    try {
        const hemirad::FormFactors F = hemirad::parseFormFactors(name, bytes);
        for (std::size_t i = 0; i < F.size(); ++i) (void)F.rowSum(i);
    } catch (const hemirad::Error&) {
    }
    return 0;
}
