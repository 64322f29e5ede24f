// The memory check: Linux reports what is available, a small request
// passes, one beyond any machine is refused in one line naming it.

#include "jade/core/error.h"
#include "jade/core/memory.h"

#include <catch2/catch.hpp>

using namespace jade;

TEST_CASE("memory: what is available is known, and requests beyond it are refused", "[memory]") {
    const std::uint64_t available = available_memory_bytes();
    CHECK(available > 0);
    CHECK_NOTHROW(require_memory(1 << 20, "a small thing"));
    CHECK_THROWS_WITH(require_memory(available * 2 + (1ULL << 30), "--resolution 4096"),
                      Catch::StartsWith("--resolution 4096 needs about") && Catch::Contains("are available"));
}
