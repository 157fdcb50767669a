// The names of an enum's values as one table in the enum's order, instead of a switch per enum.
#pragma once

#include <cstddef>

namespace rt {

/// names[e] for an enum whose values are 0, 1, 2, ... in the table's order; `past` for a value
/// outside the table.
template <class E, std::size_t N>
constexpr const char* enum_name(E e, const char* const (&names)[N], const char* past = "") {
    const auto i = static_cast<std::size_t>(e);
    return i < N ? names[i] : past;
}

}  // namespace rt
