// Placeholder until check lands.
#include "tpmsfill/check.hpp"

namespace tpmsfill {
bool MeshCheck::valid() const {
  return false;
}
std::vector<std::string> MeshCheck::problems() const {
  return {"not implemented"};
}
MeshCheck check_mesh(const TriangleSoup& soup, const CheckOptions&) {
  MeshCheck c;
  c.triangles = soup.triangles.size();
  return c;
}
std::string to_json(const MeshCheck&) {
  return "{}";
}
}  // namespace tpmsfill
