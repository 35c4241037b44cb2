#pragma once
// Name tables for enums that users see: one table per enum, shared by the scene-file reader, the
// Scene IR writer and reader, and every error message that lists the allowed values. A table is a
// specialisation of EnumNames<E> holding {value, name} pairs in the order messages list them.
//
//   template <> struct EnumNames<Colour> {
//       static constexpr std::string_view what = "colour";
//       static constexpr EnumName<Colour> table[] = {{Colour::Red, "red"}, {Colour::Blue, "blue"}};
//   };
//   nameOf(Colour::Red) == "red";  parseName<Colour>("blue") == Colour::Blue;
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace littoral {

template <class E> struct EnumName {
    E value;
    std::string_view name;
};

template <class E> struct EnumNames;  // specialised next to each enum

template <class E> std::string_view nameOf(E e) {
    for (const auto& n : EnumNames<E>::table)
        if (n.value == e) return n.name;
    return "?";
}

template <class E> std::optional<E> parseName(std::string_view s) {
    for (const auto& n : EnumNames<E>::table)
        if (n.name == s) return n.value;
    return std::nullopt;
}

template <class E> std::vector<std::string> allNames() {
    std::vector<std::string> v;
    for (const auto& n : EnumNames<E>::table) v.emplace_back(n.name);
    return v;
}

}  // namespace littoral
