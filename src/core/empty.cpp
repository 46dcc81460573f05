// Placeholder translation unit for a module whose folder has no sources yet.
