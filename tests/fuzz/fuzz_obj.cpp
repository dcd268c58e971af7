// libFuzzer harness: OBJ + MTL parsing. The input is an OBJ; after a line "#@MTL" the rest is the
// text of every material library the OBJ names. Any input must end in a scene or a hemirad::Error.
#include "engine/error.hpp"
#include "engine/obj_loader.hpp"
#include "engine/subdivide.hpp"

#include <cstddef>
#include <cstdint>
#include <string>

namespace {

class InMemory final : public hemirad::MaterialSource {
public:
    explicit InMemory(std::string text) : m_text(std::move(text)) {}
    bool find(const std::string& name, std::string& text, std::string& file) override {
        if (name == "missing.mtl") return false;
        text = m_text;
        file = name;
        return true;
    }

private:
    std::string m_text;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string input(reinterpret_cast<const char*>(data), size);
    const std::size_t split = input.find("#@MTL\n");
    InMemory libraries(split == std::string::npos ? std::string() : input.substr(split + 6));
    hemirad::Warnings warnings(nullptr);
    try {
        const hemirad::Scene scene = hemirad::parseObj("fuzz.obj", input.substr(0, split), libraries, warnings);
        // What a loaded scene feeds next: measures and the subdivision grid (bounded in size).
        (void)scene.geometryHash();
        if (scene.size() < 64) (void)hemirad::subdivide(scene, scene.extent() / 4 + 1e-9);
    } catch (const hemirad::Error&) {
    }
    return 0;
}
