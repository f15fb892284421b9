//! Validation rows that are also training rows, and the training rows themselves: a model
//! measured on the data it learnt reports a training error, far below its error on unseen
//! profiles, so `validate` warns when the validation file is the training file (same
//! fingerprint) or shares rows with it; and it retrains its comparisons only on the very
//! table a model's sidecar records.
use std::collections::HashSet;
use std::path::Path;

use schema::Fingerprint;

use crate::data::dataset::Dataset;
use crate::data::mapping::Mapping;
use crate::data::samples::Samples;
use crate::error::{Result, SurrogateError};
use crate::models::model::TrainedModel;
use crate::models::model_meta::TrainingData;

/// Whether `fingerprint` (FNV-1a 64 of a table's bytes) is the one `recorded` holds.
fn is_recorded(recorded: &TrainingData, fingerprint: Fingerprint) -> bool {
    fingerprint == recorded.fnv1a_64
}

/// Number of rows of `validation` whose features and outputs equal, bit for bit, those of
/// a row of `training`.
pub fn shared_rows(training: &Samples, validation: &Samples) -> usize {
    let key = |s: &Samples, i: usize| -> Vec<u64> {
        s.features
            .row(i)
            .iter()
            .chain(s.outputs.row(i))
            .map(|x| x.to_bits())
            .collect()
    };
    let seen: HashSet<Vec<u64>> = (0..training.n_rows()).map(|i| key(training, i)).collect();
    (0..validation.n_rows())
        .filter(|&i| seen.contains(&key(validation, i)))
        .count()
}

/// A warning if `validation` (the rows of `data` that `model`'s mapping reads) is, or
/// overlaps, the data `model` was trained on (the file its sidecar names, when it still
/// holds the recorded bytes, found from the model folder `models` as
/// [`crate::models::model_meta::ModelMeta::training_file`] says); `None` when they are disjoint or the training file is gone.
pub fn overlap_warning(
    model: &TrainedModel,
    models: &Path,
    data: &Dataset,
    validation: &Samples,
) -> Option<String> {
    let meta = model.meta();
    let recorded = &meta.training_data;
    if is_recorded(recorded, data.fingerprint()) {
        return Some(format!(
            "{} holds the very bytes model `{}` was trained on ({}): its errors are training \
             errors, not validation errors",
            data.source_name(),
            meta.mapping,
            recorded.source
        ));
    }
    let training = Dataset::read_csv(meta.training_file(models))
        .ok()
        .filter(|t| is_recorded(recorded, t.fingerprint()))?;
    let mapping = Mapping::by_name(&meta.mapping).ok()?;
    let training = Samples::from_dataset(&training, mapping).ok()?;
    let shared = shared_rows(&training, validation);
    (shared > 0).then(|| {
        format!(
            "{shared} of the {} validation rows of model `{}` are also training rows (of {}): \
             its errors are partly training errors",
            validation.n_rows(),
            meta.mapping,
            recorded.source
        )
    })
}

/// The rows `mapping` reads of the table at `path`, when it is the table `model` was
/// trained on (the fingerprint its sidecar records); [`SurrogateError::NotTrainingData`]
/// when it holds other bytes.
pub fn training_samples(model: &TrainedModel, mapping: &Mapping, path: &Path) -> Result<Samples> {
    let samples = Samples::from_dataset(&Dataset::read_csv(path)?, mapping)?;
    if is_recorded(&model.meta().training_data, samples.source_fingerprint) {
        Ok(samples)
    } else {
        Err(SurrogateError::NotTrainingData {
            path: path.to_path_buf(),
            model: mapping.name.to_owned(),
        })
    }
}
