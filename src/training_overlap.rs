//! Validation rows that are also training rows: a model measured on the data it learnt
//! reports a training error, far below its error on unseen profiles. `validate` warns when
//! the validation file is the training file (same fingerprint) or shares rows with it.
use std::collections::HashSet;
use surrogate::{Dataset, Samples, TrainedModel};

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
/// holds the recorded bytes); `None` when they are disjoint or the training file is gone.
pub fn warning(
    model: &TrainedModel,
    models: &std::path::Path,
    data: &Dataset,
    validation: &Samples,
) -> Option<String> {
    let meta = model.meta();
    let recorded = &meta.training_data;
    if format!("{:016x}", data.fingerprint()) == recorded.fnv1a_64 {
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
        .filter(|t| format!("{:016x}", t.fingerprint()) == recorded.fnv1a_64)?;
    let mapping = surrogate::Mapping::by_name(&meta.mapping).ok()?;
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
