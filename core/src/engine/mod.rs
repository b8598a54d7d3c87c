//! The one streaming `Engine` that the CLI and the plugin both drive. (Being built: issue 4.)
