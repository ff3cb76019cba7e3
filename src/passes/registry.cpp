#include "retarget/passes/registry.hpp"

#include "retarget/passes/com_plan.hpp"
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
      info<RefineIpoptPass>(false),  // ablation: the former refine (stance only at its knots, 5-20x slower)
      info<GroundPass>(),
      // com-plan: a whole-clip COM plan over the known footsteps, so the exported ZMP stays in the
      // support (issue 14); --no-com-plan leaves the kinematic reference as it is. com-replan (the
      // paper's windowed closed form, shifts clipped to 5 cm) stays for ablation: run after com-plan
      // it overwrites the planned COM with its own.
      info<ComPlanPass>(), info<ComReplanPass>(false), info<ResamplePass>(),
  };
  return registry;
}

}  // namespace rt
