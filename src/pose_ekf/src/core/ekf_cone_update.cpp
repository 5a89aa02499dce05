// Update<kConeDof>, the per-cone update's (cone_update.cpp), instantiated in a source of its own (ekf_update.h).
#include "ekf_update.h"

namespace pose_ekf {

template UpdateResult EkfCore::Update<kConeDof>(const ConeVector&, const ConeJacobian&, const ConeMatrix&, double*);

}  // namespace pose_ekf
