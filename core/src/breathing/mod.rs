//! The speech-breathing model of Bernardet et al.: parameters (Table 1, Equation 1), presets,
//! the breath cycle, breath sounds and the text chunker. (Being built: issue 3.)
