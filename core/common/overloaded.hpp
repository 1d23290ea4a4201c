// An overload set from lambdas, for std::visit: a visit names each alternative it handles.
#pragma once

namespace impactid {

template <class... Visitors>
struct Overloaded : Visitors... {
  using Visitors::operator()...;
};
template <class... Visitors>
Overloaded(Visitors...) -> Overloaded<Visitors...>;

}  // namespace impactid
