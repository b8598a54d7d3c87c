//! Online GMM head pose after van Welbergen et al. and Le et al.: EM training, the model file,
//! and per-frame synthesis. (Being built: issue 5.)
