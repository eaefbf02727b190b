/* semloc — registers semloc's serializable classes with MRPT when libsemloc.so is
 * loaded (also through `rawlog-edit -p libsemloc.so`). IMPLEMENTS_SERIALIZABLE does
 * not register by itself: without this, reading a rawlog stops silently at the first
 * semloc object. */
#include <mrpt/core/initializer.h>
#include <mrpt/rtti/CObject.h>
#include <semloc/models/camera/CBearingCameraMap.h>
#include <semloc/models/compass/CCompassMap.h>
#include <semloc/models/fix/CPoseFixMap.h>
#include <semloc/models/forwardsonar/CForwardSonarMap.h>
#include <semloc/models/semantic/CSemanticMap.h>
#include <semloc/models/sidescan/CSideScanMap.h>
#include <semloc/models/structure/CStructureMap.h>
#include <semloc/observation/CObservationDepth.h>
#include <semloc/observation/CObservationSemantic.h>

MRPT_INITIALIZER(semloc_registerAllClasses)
{
    mrpt::rtti::registerClass(CLASS_ID(semloc::CObservationSemantic));
    mrpt::rtti::registerClass(CLASS_ID(semloc::CSemanticMap));
    mrpt::rtti::registerClass(CLASS_ID(semloc::CStructureMap));
    mrpt::rtti::registerClass(CLASS_ID(semloc::CObservationDepth));
    mrpt::rtti::registerClass(CLASS_ID(semloc::CSideScanMap));
    mrpt::rtti::registerClass(CLASS_ID(semloc::CForwardSonarMap));
    mrpt::rtti::registerClass(CLASS_ID(semloc::CBearingCameraMap));
    mrpt::rtti::registerClass(CLASS_ID(semloc::CCompassMap));
    mrpt::rtti::registerClass(CLASS_ID(semloc::CPoseFixMap));
    mrpt::rtti::registerClass(CLASS_ID(semloc::CObservationDepth));
    mrpt::rtti::registerClass(CLASS_ID(semloc::CSideScanMap));
    mrpt::rtti::registerClass(CLASS_ID(semloc::CForwardSonarMap));
    mrpt::rtti::registerClass(CLASS_ID(semloc::CBearingCameraMap));
    mrpt::rtti::registerClass(CLASS_ID(semloc::CCompassMap));
    mrpt::rtti::registerClass(CLASS_ID(semloc::CPoseFixMap));
}
