// registry.cpp: the kernel instances, the one mutable object at file scope. The FreeFEM
// functions act on the current instance; a script may make another (contactKernelNew) and
// switch between them (contactKernelUse). A run uses one; each pilot run of -adapt makes its
// own and deletes it (edp/lib/adapt.idp); tests/kernel_check.edp makes two and checks that
// they share nothing, the evidence that the kernel's whole state is its Kernel value.
#include <memory>
#include "kernel.hpp"

namespace contactkernel {
namespace {
struct Registry {
  std::vector<std::unique_ptr<Kernel>> instances;   // by id; a deleted one is null
  long current = 0;
  Registry() { instances.emplace_back(new Kernel()); }
};
Registry registry;

Kernel *instance(long id) {
  return id >= 0 && id < (long)registry.instances.size() ? registry.instances[id].get() : nullptr;
}
}  // namespace

Kernel &currentKernel() { return *registry.instances[registry.current]; }

long newKernel() {
  registry.instances.emplace_back(new Kernel());
  registry.current = (long)registry.instances.size() - 1;
  return registry.current;
}

long useKernel(long id) {
  if (!instance(id)) kernelError("contactKernelUse: no kernel instance " + std::to_string(id));
  const long previous = registry.current;
  registry.current = id;
  return previous;
}

long currentKernelId() { return registry.current; }

void deleteKernel(long id) {
  if (!instance(id)) kernelError("contactKernelDelete: no kernel instance " + std::to_string(id));
  if (id == registry.current) kernelError("contactKernelDelete: instance " + std::to_string(id) + " is the current one");
  registry.instances[id].reset();
}

}  // namespace contactkernel
