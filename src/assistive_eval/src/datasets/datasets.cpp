// The dataset kinds of import_dataset: one reader per file (kitti.cpp, euroc.cpp, pairs.cpp).
#include <assistive_eval/datasets.h>

#include "dataset_io.h"

namespace assistive_eval
{
std::unique_ptr<DatasetSource> openDataset(const std::string& kind, const std::string& dir,
                                           const DatasetOptions& options)
{
  if (kind == "kitti")
    return openKitti(dir, options.kitti_truth);
  if (kind == "euroc")
    return openEuroc(dir);
  if (kind == "pairs")
    return openPairs(dir);
  dataset_io::fail("unknown dataset kind '" + kind + "' (kitti, euroc or pairs)");
}
}  // namespace assistive_eval
