#include "retarget/passes/registry.hpp"

#include "retarget/passes/com_replan.hpp"
#include "retarget/passes/flat_contact.hpp"
#include "retarget/passes/ground.hpp"
#include "retarget/passes/ik_pass.hpp"
#include "retarget/passes/label_contacts.hpp"
#include "retarget/passes/refine.hpp"
#include "retarget/passes/refine_ipopt.hpp"
#include "retarget/passes/resample.hpp"
#include "retarget/passes/retime.hpp"
#include "retarget/passes/scale.hpp"

namespace rt {

namespace {
template <class P>
PassInfo info(bool in_default = true) {
  P probe;
  return {probe.name(), probe.description(), in_default, [] { return std::make_unique<P>(); }};
}
}  // namespace

const PassRegistry& builtin_passes() {
  static const PassRegistry registry = {
      // label-contacts only needs the source motion; running it before ik lets ik hold planted feet.
      info<RetimePass>(),      info<ScalePass>(),         info<LabelContactsPass>(), info<IkPass>(), info<FlatContactPass>(), info<RefinePass>(),
      // com-replan is opt-in (--com-replan): measured on the shared clips, its COM-following IK
      // breaks the feet's kinematic bounds on H1 (no ankle roll: skating, 1-15 cm penetration after
      // rate limiting) and did not change a dynamics-check outcome on the walking clips; the check
      // re-plans online anyway (paper §VI).
      info<RefineIpoptPass>(false),  // ablation: the former refine (stance only at its knots, 5-20x slower)
      info<GroundPass>(),      info<ComReplanPass>(false), info<ResamplePass>(),
  };
  return registry;
}

}  // namespace rt
