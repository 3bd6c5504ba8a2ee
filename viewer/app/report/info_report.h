// What `ultrafusion info` (and run's dataset stage) found in a dataset (pipeline::DatasetSummary: per stream
// its description, time diagnostics and LiDAR points per scan), printed as a table or as JSON.
#pragma once

#include <ostream>
#include <vector>

#include "viewer/pipeline/stages/dataset_stage.h"

namespace uf::app {

using pipeline::DatasetSummary;
using pipeline::StreamSummary;

void PrintDatasetTable(std::ostream& out, const DatasetSummary& summary);
void PrintDatasetJson(std::ostream& out, const DatasetSummary& summary);

}  // namespace uf::app
