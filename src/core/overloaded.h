// std::visit over a variant with one lambda per alternative: a variant that gains an
// alternative fails to compile at every visit that does not handle it.
#pragma once

namespace pgt {

template <class... F>
struct Overloaded : F... {
    using F::operator()...;
};
template <class... F>
Overloaded(F...) -> Overloaded<F...>;

}  // namespace pgt
