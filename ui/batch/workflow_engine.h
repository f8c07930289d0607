// `sylva batch --engine snakemake`: the same batch through the Snakemake 7
// workflow in workflow/ (one job per tree, each `sylva batch MANIFEST OUT_DIR
// --only NAME`), locally or on a Slurm cluster by profile. Snakemake runs as
// a child process with this terminal's output; its working folder (its
// .snakemake/ metadata, Slurm logs) is OUT_DIR.
#ifndef SYLVA_UI_BATCH_WORKFLOW_ENGINE_H_
#define SYLVA_UI_BATCH_WORKFLOW_ENGINE_H_

#include <filesystem>
#include <string>
#include <vector>

#include "ui/batch/batch_runner.h"
#include "ui/batch/manifest.h"

namespace sylva {

// The workflow folder: $SYLVA_WORKFLOW_DIR, else the source tree's workflow/.
std::filesystem::path WorkflowDir();

// A profile: an existing folder, or a name under WorkflowDir()/profiles/
// ("local", "slurm"). Throws InputError naming --profile if neither exists.
std::filesystem::path ResolveProfile(const std::string& profile);

// The snakemake command line for the batch.
std::vector<std::string> SnakemakeArguments(const Manifest& manifest,
                                            const std::filesystem::path& out_dir,
                                            const std::filesystem::path& profile,
                                            const BatchOptions& options);

// Runs snakemake (found on PATH) and then rewrites the summary. Returns the
// batch's exit code as RunBatch's: 0 when every tree finished,
// kBatchExitTreesFailed when some failed, 1 when Snakemake failed otherwise.
// Throws InputError if snakemake cannot be started.
int RunSnakemakeBatch(const Manifest& manifest, const std::filesystem::path& out_dir,
                      const std::filesystem::path& profile, const BatchOptions& options);

}  // namespace sylva

#endif  // SYLVA_UI_BATCH_WORKFLOW_ENGINE_H_
